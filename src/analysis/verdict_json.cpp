#include "hrgbench/analysis/verdict_json.hpp"

#include <string>

#include "hrgbench/analysis/estimate_report_json.hpp"
#include "hrgbench/session/session_record_keys.hpp"

namespace hrgbench::bench {

namespace keys = session::keys;

nlohmann::json VerdictJson(const Verdict& verdict) {
  nlohmann::json checks = nlohmann::json::array();
  for (const FitCheck& c : verdict.fit_checks) {
    checks.push_back({{"run", c.run_id},
                      {"name", c.name},
                      {"status", std::string(ToString(c.status))},
                      {"value", NumberOrNull(c.value)},
                      {"max", NumberOrNull(c.max)},
                      {"message", c.message}});
  }
  nlohmann::json limits = nlohmann::json::array();
  for (const LimitResult& r : verdict.results) {
    limits.push_back({{"quantity", std::string(ToString(r.quantity))},
                      {"status", std::string(ToString(r.status))},
                      {"value", NumberOrNull(r.value)},
                      {"std", NumberOrNull(r.std)},
                      {"min", NumberOrNull(r.min)},
                      {"max", NumberOrNull(r.max)},
                      {"message", r.message},
                      {keys::kRule, std::string(ToString(r.rule))},
                      {keys::kZone, std::string(ToString(r.zone))},
                      {keys::kCoverageFactor, NumberOrNull(r.coverage_factor)},
                      {keys::kExpandedUncertainty, NumberOrNull(r.expanded_uncertainty)},
                      {keys::kIntervalMin, NumberOrNull(r.interval_min)},
                      {keys::kIntervalMax, NumberOrNull(r.interval_max)},
                      {keys::kAcceptanceMin, NumberOrNull(r.acceptance_min)},
                      {keys::kAcceptanceMax, NumberOrNull(r.acceptance_max)},
                      {keys::kRetest, r.retest}});
  }
  nlohmann::json decision = {{keys::kRule, std::string(ToString(verdict.decision.kind))},
                             {keys::kCoverageFactor, verdict.decision.coverage_factor}};
  if (verdict.decision.kind == DecisionRuleKind::kSimpleAcceptance)
    decision[keys::kMaxUncertaintyRatio] = verdict.decision.max_uncertainty_ratio;
  return {{"overall", std::string(ToString(verdict.overall))},
          {"fit_acceptable", verdict.fit_acceptable},
          {"fit_checks", checks},
          {"limits", limits},
          {keys::kDecision, decision},
          {keys::kRetest, verdict.retest}};
}

}  // namespace hrgbench::bench
