#pragma once
// A run's Ω as the sequencer measures it (internal to the sequencer): the table's rate at every
// table read of the run loop, its angle at the release, at every table read and after the
// capture (include/hrgbench/bench/capture/run_omega.hpp computes both). Both are kept in the
// record; the station's [table] omega_source says which one the estimator gets. Owner thread only
// (the sequencer's); the angle readings go into room reserved by the constructor.

#include <cstddef>
#include <string>

#include "bench/sequencer/run_context.hpp"
#include "hrgbench/bench/capture/run_omega.hpp"
#include "hrgbench/config/station_config.hpp"
#include "hrgbench/hw/rate_table.hpp"
#include "hrgbench/session/session_record_types.hpp"

namespace hrgbench::bench::internal {

class RunOmegaReadings {
 public:
  // `expected_reads`: how many angle reads to make room for (the run's loop periods + a few).
  RunOmegaReadings(OmegaSourceSetting setting, std::size_t expected_reads);

  void AddRate(double measured_rate_rad_s) { rate_.Add(measured_rate_rad_s); }

  // One angle read. A table without an angle (kNotSupported) is not asked again this run; that
  // is an error only when the station asks for the angle. Transport errors are errors.
  StepOutcome ReadAngle(hw::RateTable& table, int run_id);

  // Fills the Ω fields of `end` in the unit's frame: `axis_sign` × the table's measurement (−1 for
  // a unit mounted against the table's axis) + the Earth-rate component on the unit's axis; with
  // no rate reading either, `measured_at_start_rad_s` (the unit's frame) stands in. An error when
  // the station asks for the angle and there is no Ω from it.
  StepOutcome Finish(int axis_sign, double earth_rate_rad_s, double measured_at_start_rad_s,
                     RunEnd& end) const;

  // Why the angle gave no Ω, for the log.
  std::string NoAngleReason() const;

 private:
  OmegaSourceSetting setting_;
  bool angle_reported_ = true;
  std::string no_angle_reason_;
  RateReadingsMean rate_;
  AngleRateFit angle_;
};

}  // namespace hrgbench::bench::internal
