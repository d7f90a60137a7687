#pragma once
// The resonant frequency f0 of a session's gyro, as its electronics reported it: what turns the
// estimate's decay time into Q (estimator/engineering_quantities.hpp). The estimator cannot give
// it: f0 does not enter the slow model.
//
// From the record (session::SessionRecord, read by the session layer's one reader): the mean of
// runs[].start.resonant_frequency_hz over the complete runs that recorded a finite, positive value
// (the electronics' Status at each release). NaN, with the source saying so, when no run did
// (sessions written by hrg-sim, older records).
//
// Pure function; never throws except std::bad_alloc.

#include <limits>
#include <string>

#include "hrgbench/session/session_record.hpp"

namespace hrgbench::bench {

struct RecordedFrequency {
  double hz = std::numeric_limits<double>::quiet_NaN();
  double spread_hz = std::numeric_limits<double>::quiet_NaN();  // max − min over the runs
  int runs = 0;                                                 // runs it was averaged over
  std::string source;  // "electronics status at the release of 6 runs (spread 0.002 Hz)"
};

RecordedFrequency RecordedResonantFrequency(const session::SessionRecord& record);

}  // namespace hrgbench::bench
