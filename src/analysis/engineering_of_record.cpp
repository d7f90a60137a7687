#include "hrgbench/analysis/engineering_of_record.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "hrgbench/analysis/recorded_frequency.hpp"
#include "hrgbench/session/session_record_keys.hpp"

namespace hrgbench::bench {

nlohmann::json PickoffDeclarationJson(const PickoffDeclaration& declaration) {
  return {{session::keys::kCrossTalkStage, estimator::ToString(declaration.cross_talk_stage)},
          {session::keys::kUnmodelledCouplingBoundRad, declaration.unmodelled_coupling_bound_rad}};
}

RecordedPickoff RecordedPickoffDeclaration(const session::ElectronicsRecord& electronics) {
  RecordedPickoff out;
  if (electronics.pickoff) {
    out.declaration = *electronics.pickoff;
  } else {
    out.note =
        "session.json has no electronics.pickoff (recorded before the pick-off was declared): "
        "cross-talk stage midway, no bound on an unmodelled coupling";
  }
  return out;
}

EngineeringOfRecord ComputeEngineeringOfRecord(const estimator::EstimateSummary& summary,
                                               const session::SessionRecord& record) {
  const RecordedPickoff pickoff = RecordedPickoffDeclaration(record.electronics);
  const RecordedFrequency f0 = RecordedResonantFrequency(record);
  estimator::EngineeringOptions options;
  options.cross_talk_stage = pickoff.declaration.cross_talk_stage;
  options.unmodelled_coupling_bound_rad = pickoff.declaration.unmodelled_coupling_bound_rad;
  // The electronics state no uncertainty of their f0; what the record shows is how far it moved
  // over the runs, which Q's f0 (their mean) is uncertain by: rectangular over the range.
  if (f0.runs >= 2 && std::isfinite(f0.spread_hz)) {
    options.frequency_std_hz = f0.spread_hz / std::sqrt(12.0);
    options.frequency_std_source = "the spread of the runs' reported f0 (rectangular over " +
                                   std::to_string(f0.runs) +
                                   " runs); the electronics state no uncertainty of their own";
  }
  // The longest free run the record planned (the splits follow f over it under a drift).
  double longest = 0.0;
  for (const session::RunRecord& run : record.runs) {
    if (run.plan && std::isfinite(run.plan->free_run_s))
      longest = std::max(longest, run.plan->free_run_s);
  }
  if (longest > 0.0) options.longest_run_s = longest;
  EngineeringOfRecord out;
  out.quantities = estimator::ComputeEngineeringQuantities(summary, f0.hz, options);
  out.frequency_source = f0.source;
  if (!pickoff.note.empty()) out.notes.push_back(pickoff.note);
  return out;
}

}  // namespace hrgbench::bench
