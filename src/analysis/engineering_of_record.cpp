#include "hrgbench/analysis/engineering_of_record.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "hrgbench/analysis/recorded_frequency.hpp"

namespace hrgbench::bench {
namespace {

std::optional<estimator::CrossTalkStage> ParseStage(const std::string& text) {
  for (const estimator::CrossTalkStage stage :
       {estimator::CrossTalkStage::kMidway, estimator::CrossTalkStage::kBeforeGain,
        estimator::CrossTalkStage::kAfterGain}) {
    if (text == estimator::ToString(stage)) return stage;
  }
  return std::nullopt;
}

}  // namespace

nlohmann::json PickoffDeclarationJson(const PickoffDeclaration& declaration) {
  return {{"cross_talk_stage", estimator::ToString(declaration.cross_talk_stage)},
          {"unmodelled_coupling_bound_rad", declaration.unmodelled_coupling_bound_rad}};
}

std::expected<RecordedPickoff, std::string> RecordedPickoffDeclaration(
    const nlohmann::json& document) {
  RecordedPickoff out;
  const nlohmann::json* pickoff = nullptr;
  if (document.is_object() && document.contains("electronics") &&
      document.at("electronics").is_object() && document.at("electronics").contains("pickoff"))
    pickoff = &document.at("electronics").at("pickoff");
  if (pickoff == nullptr) {
    out.note =
        "session.json has no electronics.pickoff (recorded before the pick-off was declared): "
        "cross-talk stage midway, no bound on an unmodelled coupling";
    return out;
  }
  if (!pickoff->is_object())
    return std::unexpected("field 'electronics.pickoff': expected an object, got " +
                           pickoff->dump());
  if (pickoff->contains("cross_talk_stage")) {
    const nlohmann::json& stage = pickoff->at("cross_talk_stage");
    const auto parsed = stage.is_string() ? ParseStage(stage.get<std::string>()) : std::nullopt;
    if (!parsed)
      return std::unexpected(
          "field 'electronics.pickoff.cross_talk_stage': expected \"midway\", \"before_gain\" or "
          "\"after_gain\", got " +
          stage.dump());
    out.declaration.cross_talk_stage = *parsed;
  }
  if (pickoff->contains("unmodelled_coupling_bound_rad")) {
    const nlohmann::json& bound = pickoff->at("unmodelled_coupling_bound_rad");
    const double value = bound.is_number() ? bound.get<double>() : estimator::kNaN;
    if (!(std::isfinite(value) && value >= 0.0 && value <= kMaxCouplingBoundRad))
      return std::unexpected(
          "field 'electronics.pickoff.unmodelled_coupling_bound_rad': expected a number in [0, " +
          nlohmann::json(kMaxCouplingBoundRad).dump() + "], got " + bound.dump());
    out.declaration.unmodelled_coupling_bound_rad = value;
  }
  return out;
}

std::expected<EngineeringOfRecord, std::string> ComputeEngineeringOfRecord(
    const estimator::EstimateSummary& summary, const nlohmann::json& document) {
  const auto pickoff = RecordedPickoffDeclaration(document);
  if (!pickoff) return std::unexpected(pickoff.error());
  const RecordedFrequency f0 = RecordedResonantFrequency(document);
  estimator::EngineeringOptions options;
  options.cross_talk_stage = pickoff->declaration.cross_talk_stage;
  options.unmodelled_coupling_bound_rad = pickoff->declaration.unmodelled_coupling_bound_rad;
  // The electronics state no uncertainty of their f0; what the record shows is how far it moved
  // over the runs, which Q's f0 (their mean) is uncertain by: rectangular over the range.
  if (f0.runs >= 2 && std::isfinite(f0.spread_hz)) {
    options.frequency_std_hz = f0.spread_hz / std::sqrt(12.0);
    options.frequency_std_source = "the spread of the runs' reported f0 (rectangular over " +
                                   std::to_string(f0.runs) +
                                   " runs); the electronics state no uncertainty of their own";
  }
  // The longest free run the record planned (the splits follow f over it under a drift).
  if (document.is_object() && document.contains("runs") && document.at("runs").is_array()) {
    double longest = 0.0;
    for (const nlohmann::json& run : document.at("runs")) {
      if (!run.is_object() || !run.contains("plan") || !run.at("plan").is_object()) continue;
      const nlohmann::json& plan = run.at("plan");
      if (plan.contains("free_run_s") && plan.at("free_run_s").is_number())
        longest = std::max(longest, plan.at("free_run_s").get<double>());
    }
    if (longest > 0.0) options.longest_run_s = longest;
  }
  EngineeringOfRecord out;
  out.quantities = estimator::ComputeEngineeringQuantities(summary, f0.hz, options);
  out.frequency_source = f0.source;
  if (!pickoff->note.empty()) out.notes.push_back(pickoff->note);
  return out;
}

}  // namespace hrgbench::bench
