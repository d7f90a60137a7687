#pragma once
// The engineering quantities of a session's record: the one place that turns a record's estimate
// into the unit's physical quantities with their budget (estimator/engineering_quantities.hpp),
// with what the record declares about the electronics. The verdict, the estimate of record, the
// report and hrg-estimate all call it, so they judge and show the same numbers.
//
// What it reads of session.json:
//   runs[].start.resonant_frequency_hz   f0 (recorded_frequency.hpp); the spread of the runs'
//                                        values is f0's "as reported" component (rectangular over
//                                        the range: spread/√12), when two or more runs have it
//   electronics.pickoff                  what the station declares of its pick-off ([gyro]
//                                        pickoff_cross_talk_stage, pickoff_coupling_bound_rad):
//                                        {"cross_talk_stage": "midway" | "before_gain" |
//                                        "after_gain", "unmodelled_coupling_bound_rad": ≥ 0};
//                                        absent (a record from before it was declared): midway, no
//                                        bound, and a note
//
// Failure: a declaration this reader does not know is an error naming the field and the value
// (guessing would change the quantities silently).

#include <expected>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hrgbench/estimator/engineering_quantities.hpp"
#include "hrgbench/estimator/summary.hpp"
#include "hrgbench/session/electronics.hpp"

namespace hrgbench::bench {

nlohmann::json PickoffDeclarationJson(const PickoffDeclaration& declaration);

struct RecordedPickoff {
  PickoffDeclaration declaration;
  std::string note;  // non-empty when the record had none
};
std::expected<RecordedPickoff, std::string> RecordedPickoffDeclaration(
    const nlohmann::json& session_document);

struct EngineeringOfRecord {
  estimator::EngineeringQuantities quantities;
  std::string frequency_source;    // where f0 came from (RecordedFrequency::source)
  std::vector<std::string> notes;  // a missing declaration, and the like
};
std::expected<EngineeringOfRecord, std::string> ComputeEngineeringOfRecord(
    const estimator::EstimateSummary& summary, const nlohmann::json& session_document);

}  // namespace hrgbench::bench
