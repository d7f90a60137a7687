#include "hrgbench/analysis/verdict.hpp"

#include <cmath>
#include <cstdio>

namespace hrgbench::bench {
namespace {

std::string Number(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.7g", v);
  return text;
}

struct Value {
  double value = estimator::kNaN;
  double std = estimator::kNaN;
  bool held_fixed = false;
};

Value ValueOf(const estimator::EstimateSummary& s,
              const estimator::EngineeringQuantities& engineering, LimitedQuantity q,
              std::string* not_determined) {
  if (const auto e = EngineeringOf(q)) {
    const estimator::EngineeringValue& v = engineering[*e];
    if (!v.determined) *not_determined = v.note.empty() ? "not determined" : v.note;
    return {v.value, v.std, false};
  }
  const auto index = static_cast<int>(q);
  if (index <= static_cast<int>(LimitedQuantity::kDelta6)) {
    return {s.delta(index), s.delta_std(index),
            !s.delta_estimated[static_cast<std::size_t>(index)]};
  }
  if (index <= static_cast<int>(LimitedQuantity::kXi4)) {
    const int i = index - static_cast<int>(LimitedQuantity::kXi1);
    return {s.xi(i), s.xi_std(i), !s.xi_estimated[static_cast<std::size_t>(i)]};
  }
  if (q == LimitedQuantity::kResidualRms) return {s.residual_rms, estimator::kNaN, false};
  return {s.noise_sigma, estimator::kNaN, false};
}

// The decision of one finite value v with standard uncertainty u (NaN: none reported) against
// its limit under `rule` (decision.hpp); fills the result's status, zone, interval, message.
void Decide(const ParameterLimit& limit, const DecisionRule& rule, double v, double u,
            const std::string& shown, const std::string& range, LimitResult* result) {
  // The low side is a tolerance only above the physical bound (a magnitude's 0 is not one).
  const Decision d = bench::Decide(v, u, limit.min, limit.max,
                                   limit.min > PhysicalMinimum(limit.quantity), rule, shown, range);
  result->status = d.status;
  result->zone = d.zone;
  result->expanded_uncertainty = d.expanded_uncertainty;
  result->interval_min = d.interval_min;
  result->interval_max = d.interval_max;
  result->acceptance_min = d.acceptance_min;
  result->acceptance_max = d.acceptance_max;
  result->retest = d.retest;
  result->message = d.message;
}

LimitResult Evaluate(const ParameterLimit& limit, const DecisionRule& rule,
                     const estimator::EstimateSummary& estimate,
                     const estimator::EngineeringQuantities& engineering) {
  LimitResult result;
  result.quantity = limit.quantity;
  result.rule = rule.kind;
  result.coverage_factor = rule.coverage_factor;
  result.min = limit.min;
  result.max = limit.max;
  const std::string name(ToString(limit.quantity));
  const std::string range = "[" + Number(limit.min) + ", " + Number(limit.max) + "]";
  if (!estimate.IsUsable()) {
    result.message = name + ": not evaluated, the estimate is unusable (" +
                     estimator::ToString(estimate.termination) + ")";
    return result;
  }
  std::string not_determined;
  const Value v = ValueOf(estimate, engineering, limit.quantity, &not_determined);
  result.value = v.value;
  result.std = v.std;
  if (!not_determined.empty()) {
    // An engineering quantity from a held parameter, an unknown f0, or the axis of a split that
    // is noise: nothing was measured to judge.
    result.value = estimator::kNaN;
    result.message = name + ": not evaluated, " + not_determined;
    return result;
  }
  if (v.held_fixed) {
    // A held value is an input, not a measurement: judging it would pass or fail the unit on
    // what the operator assumed.
    result.value = estimator::kNaN;
    result.message = name +
                     ": not evaluated, held fixed by the estimator (not determined by this "
                     "sequence or not requested)";
    return result;
  }
  if (!std::isfinite(v.value)) {
    result.message = name + ": not evaluated, the estimate has no finite value";
    return result;
  }
  const std::string shown = name + " = " + Number(v.value) +
                            (std::isfinite(v.std) ? " ± " + Number(v.std) : std::string());
  Decide(limit, rule, v.value, v.std, shown, range, &result);
  return result;
}

FitCheck Check(int run, const char* name, double value, double max, const char* meaning) {
  FitCheck check;
  check.run_id = run;
  check.name = name;
  check.value = value;
  check.max = max;
  const std::string head = "run " + std::to_string(run) + ": " + name + " = ";
  if (!std::isfinite(value)) {
    check.status = LimitStatus::kNotEvaluated;
    check.message = head + "not computed";
  } else if (value <= max) {
    check.status = LimitStatus::kPass;
    check.message = head + Number(value) + " within " + Number(max);
  } else {
    check.status = LimitStatus::kFail;
    check.message = head + Number(value) + " above " + Number(max) + " (" + meaning + ")";
  }
  return check;
}

std::vector<FitCheck> JudgeFit(const estimator::FitQualityLimits& limits,
                               const estimator::EstimateSummary& estimate) {
  std::vector<FitCheck> checks;
  if (!estimate.IsUsable()) return checks;
  if (estimate.diagnostics.runs.empty()) {
    FitCheck none;
    none.name = "fit";
    none.message = "fit: not judged, the method reports no fit diagnostics";
    checks.push_back(none);
    return checks;
  }
  for (const estimator::RunFitDiagnostics& run : estimate.diagnostics.runs) {
    checks.push_back(Check(run.run_id, "residual_ratio", run.residual_ratio,
                           estimator::ResidualRatioThreshold(limits, run.samples),
                           "residuals above the noise of the data: the model misses something"));
    if (run.noise_free) {
      FitCheck skipped = Check(run.run_id, "whiteness_z", 0.0, limits.whiteness_z_max, "");
      skipped.value = estimator::kNaN;
      skipped.message =
          "run " + std::to_string(run.run_id) + ": whiteness_z not applicable (noise-free data)";
      checks.push_back(skipped);
    } else {
      checks.push_back(Check(run.run_id, "whiteness_z", run.whiteness_z, limits.whiteness_z_max,
                             "residuals not white: coloured noise or a model error"));
    }
    if (std::isfinite(run.omega_offset_in_std))
      checks.push_back(Check(run.run_id, "omega_offset_in_std", std::abs(run.omega_offset_in_std),
                             limits.omega_offset_max_in_std,
                             "the data contradict the recorded rate"));
  }
  // What the estimate names about itself as a whole (no run's check sees it: the data fit
  // perfectly): an angular gain of the wrong sign, an I/Q convention the commanded quadrature
  // contradicts (bench::NameIqConventionContradiction). Each is a failed check of its own; the
  // per-run problems ("run N: ...") are judged above against this limits file's thresholds.
  for (const std::string& problem : estimate.diagnostics.problems) {
    if (problem.rfind("run ", 0) == 0) continue;
    FitCheck whole;
    whole.name = "estimate";
    whole.status = LimitStatus::kFail;
    whole.message = "estimate: " + problem;
    checks.push_back(whole);
  }
  return checks;
}

}  // namespace

std::vector<std::string_view> Verdict::FailedNames() const {
  std::vector<std::string_view> names;
  for (const LimitResult& r : results)
    if (r.status == LimitStatus::kFail) names.push_back(ToString(r.quantity));
  return names;
}

std::string Verdict::FitProblems() const {
  std::string text;
  for (const FitCheck& c : fit_checks)
    if (c.status != LimitStatus::kPass) text += (text.empty() ? "" : "; ") + c.message;
  return text;
}

std::string Verdict::Report() const {
  std::string text;
  for (const FitCheck& c : fit_checks) {
    if (c.status == LimitStatus::kPass) continue;
    std::string status(ToString(c.status));
    status.resize(14, ' ');
    text += status + "fit " + c.message + "\n";
  }
  if (!fit_checks.empty() && fit_acceptable)
    text += "PASS          fit: every run within its limits (" + std::to_string(fit_checks.size()) +
            " checks)\n";
  for (const LimitResult& r : results) {
    std::string status(ToString(r.status));
    status.resize(14, ' ');
    text += status + r.message + "\n";
  }
  text += "verdict: " + std::string(ToString(overall));
  std::string listed;
  for (const LimitResult& r : results) {
    if (r.status == overall && overall != LimitStatus::kPass)
      listed += (listed.empty() ? "" : ", ") + std::string(ToString(r.quantity));
  }
  if (!listed.empty()) text += " (" + listed + ")";
  if (retest) text += "; undecided within the guard band: retest";
  return text + "\n";
}

Verdict EvaluateLimits(const LimitsConfig& limits, const estimator::EstimateSummary& estimate) {
  return EvaluateLimits(limits, estimate,
                        estimator::ComputeEngineeringQuantities(estimate, estimator::kNaN));
}

Verdict EvaluateLimits(const LimitsConfig& limits, const estimator::EstimateSummary& estimate,
                       const estimator::EngineeringQuantities& engineering) {
  Verdict verdict;
  verdict.fit_checks = JudgeFit(limits.fit, estimate);
  for (const FitCheck& c : verdict.fit_checks)
    verdict.fit_acceptable = verdict.fit_acceptable && c.status == LimitStatus::kPass;
  bool any_fail = false;
  bool any_not_evaluated = false;
  verdict.decision = limits.decision;
  bool any_proven_fail = false;
  for (const ParameterLimit& limit : limits.limits) {
    LimitResult result = Evaluate(limit, limits.decision, estimate, engineering);
    if (!verdict.fit_acceptable && result.status != LimitStatus::kNotEvaluated) {
      result.message = std::string(ToString(limit.quantity)) +
                       ": not judged, the fit is outside its model (would be " +
                       std::string(ToString(result.status)) + ": " + result.message + ")";
      result.status = LimitStatus::kNotEvaluated;
      result.zone = DecisionZone::kNotJudged;
      result.retest = false;
    }
    any_proven_fail = any_proven_fail || (result.status == LimitStatus::kFail && !result.retest);
    any_fail = any_fail || result.status == LimitStatus::kFail;
    any_not_evaluated = any_not_evaluated || result.status == LimitStatus::kNotEvaluated;
    verdict.results.push_back(std::move(result));
  }
  verdict.overall = !verdict.fit_acceptable ? LimitStatus::kNotEvaluated
                    : any_fail              ? LimitStatus::kFail
                    : any_not_evaluated     ? LimitStatus::kNotEvaluated
                                            : LimitStatus::kPass;
  verdict.retest = verdict.overall == LimitStatus::kFail && !any_proven_fail;
  return verdict;
}

}  // namespace hrgbench::bench
