#pragma once
// The engineering quantities of a session's record: the one place that turns a record's estimate
// into the unit's physical quantities with their budget (estimator/engineering_quantities.hpp),
// with what the record declares about the electronics. The verdict, the estimate of record, the
// report and hrg-estimate all call it, so they judge and show the same numbers.
//
// What it uses of the record (session::SessionRecord, typed and validated by the session layer's
// one reader, so nothing here can be malformed):
//   runs[].start.resonant_frequency_hz   f0 (recorded_frequency.hpp); the spread of the runs'
//                                        values is f0's "as reported" component (rectangular over
//                                        the range: spread/√12), when two or more runs have it
//   runs[].plan.free_run_s               the longest planned free run (f's drift over it)
//   electronics.pickoff                  what the station declares of its pick-off ([gyro]
//                                        pickoff_cross_talk_stage, pickoff_coupling_bound_rad);
//                                        absent (a record from before it was declared): midway, no
//                                        bound, and a note
//
// A declaration the reader does not know is the reader's error (ReadSessionRecord names the field
// and the value: guessing would change the quantities silently). Pure functions; never throw
// except std::bad_alloc.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hrgbench/estimator/engineering_quantities.hpp"
#include "hrgbench/estimator/summary.hpp"
#include "hrgbench/session/electronics.hpp"
#include "hrgbench/session/session_record.hpp"

namespace hrgbench::bench {

nlohmann::json PickoffDeclarationJson(const PickoffDeclaration& declaration);

struct RecordedPickoff {
  PickoffDeclaration declaration;
  std::string note;  // non-empty when the record had none
};
RecordedPickoff RecordedPickoffDeclaration(const session::ElectronicsRecord& electronics);

struct EngineeringOfRecord {
  estimator::EngineeringQuantities quantities;
  std::string frequency_source;    // where f0 came from (RecordedFrequency::source)
  std::vector<std::string> notes;  // a missing declaration, and the like
};
EngineeringOfRecord ComputeEngineeringOfRecord(const estimator::EstimateSummary& summary,
                                               const session::SessionRecord& record);

}  // namespace hrgbench::bench
