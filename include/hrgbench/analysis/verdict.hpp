#pragma once
// The verdict: a LimitsConfig applied to an estimate. Each limit is PASS (conformance shown under
// the file's decision rule, below), FAIL (non-conformance shown, or not accepted within the guard
// band: the unit's, STYLE rule 9; the message names the parameter, its value and the limit) or
// NOT EVALUATED (the value does not exist: the estimate is unusable, the parameter was
// held fixed because the sequence cannot determine it, or it is not finite). NOT EVALUATED is not
// a FAIL: the unit was not shown bad, the bench did not measure it; the app reports it as ERROR.
//
// Before any limit, the fit itself is judged (always, with the limits file's [fit] or the
// defaults): per run, the residual ratio, the whiteness of the residuals and the offset of Ω the
// data ask for. A fit outside its model makes every estimated value untrustworthy, so then no
// limit is judged: each becomes NOT EVALUATED (saying what it would have been) and the verdict is
// NOT EVALUATED. A poor fit is never a PASS, and never a FAIL the unit did not earn.
//
// Each limit is decided by the limits file's rule ([decision], config/decision_rule.hpp; applied by
// decision.hpp) with the
// value's combined standard uncertainty u (the estimate's std of δ and ξ; u_c of an engineering
// quantity) and the file's coverage factor k, U = k·u:
//   guarded acceptance   PASS when [v − U, v + U] is inside the limits (conforming), FAIL when it
//                        is wholly outside (non-conforming), else undecided: not accepted, FAIL
//                        with `retest` set (guarded_acceptance_retest: measure the unit again;
//                        the record and the outcome's reason say "retest") or a plain FAIL
//                        (guarded_acceptance_reject). A limit whose acceptance zone is empty
//                        (2·U wider than the tolerance) can never be proven conforming: it is
//                        NOT EVALUATED (the sequence does not determine it) unless wholly outside.
//   simple acceptance    the point value against [min, max], when U is at most the rule's
//                        max_uncertainty_ratio of the width; otherwise NOT EVALUATED unless
//                        wholly outside (FAIL).
// A min at the quantity's physical bound (PhysicalMinimum: a magnitude's 0) is not guarded. A
// value without a reported uncertainty (residual_rms, noise_sigma) is judged on its value, and
// its message says so. The undecided zone is a FAIL with a flag rather than an outcome of its own:
// every reader of the record (store, panel, exit code) keeps the four outcomes it knows.
//
// Pure function of its inputs; thread-safe; allocates (not for real-time code).

#include <string>
#include <string_view>
#include <vector>

#include "hrgbench/analysis/decision.hpp"
#include "hrgbench/config/decision_rule.hpp"
#include "hrgbench/config/limits_config.hpp"
#include "hrgbench/estimator/engineering_quantities.hpp"
#include "hrgbench/estimator/summary.hpp"

namespace hrgbench::bench {

struct LimitResult {
  LimitedQuantity quantity = LimitedQuantity::kDelta1;
  LimitStatus status = LimitStatus::kNotEvaluated;
  double value = estimator::kNaN;  // the estimate (NaN when there is none)
  double std = estimator::kNaN;    // its standard deviation when the estimator reports one
  double min = estimator::kNaN;
  double max = estimator::kNaN;
  std::string message;  // "delta2 = 0.35 outside [0.29, 0.31] (0.04 above max)", ...
  // The decision (decision_rule.hpp). u is `std`; NaN below when the value or u is missing.
  DecisionRuleKind rule = DecisionRuleKind::kGuardedAcceptanceRetest;
  DecisionZone zone = DecisionZone::kNotJudged;
  double coverage_factor = estimator::kNaN;       // k
  double expanded_uncertainty = estimator::kNaN;  // U = k·u
  double interval_min = estimator::kNaN;          // v − U
  double interval_max = estimator::kNaN;          // v + U
  // The acceptance zone: [min + U, max − U] under a guarded rule (min itself on an unguarded
  // physical bound), [min, max] under simple acceptance.
  double acceptance_min = estimator::kNaN;
  double acceptance_max = estimator::kNaN;
  bool retest = false;  // undecided under guarded_acceptance_retest: measure the unit again
};

// One check of the fit (per run and statistic), judged against LimitsConfig::fit.
struct FitCheck {
  int run_id = 0;    // 0: the whole estimate (no diagnostics at all)
  std::string name;  // "residual_ratio", "whiteness_z", "omega_offset_in_std"
  LimitStatus status = LimitStatus::kNotEvaluated;
  double value = estimator::kNaN;
  double max = estimator::kNaN;
  std::string message;  // "run 3: residual_ratio = 22.1 above 1.05 (the model misses something)"
};

struct Verdict {
  // kNotEvaluated if the fit failed a check; else kFail if any limit failed; else kNotEvaluated
  // if any could not be evaluated; else kPass (also when there are no limits: nothing was
  // required).
  LimitStatus overall = LimitStatus::kPass;
  std::vector<FitCheck> fit_checks;  // per run: residual ratio, whiteness, Ω offset (when fitted)
  bool fit_acceptable = true;        // every fit check passed
  std::vector<LimitResult> results;  // one per limit, in the limits file's order
  DecisionRule decision;             // the rule every limit was decided with
  // Every FAIL is an undecided limit under guarded_acceptance_retest (none proven outside): the
  // unit is not accepted and goes to a retest.
  bool retest = false;

  std::vector<std::string_view> FailedNames() const;
  // The failed fit checks' messages, joined by "; " (empty when the fit is acceptable).
  std::string FitProblems() const;
  // One line per failed fit check, one per limit ("FAIL  delta2 = ..."), then
  // "verdict: FAIL (delta2)".
  std::string Report() const;
};

// `engineering`: the estimate's engineering quantities (ComputeEngineeringQuantities with the
// recorded f0), judged by the limits on them; one not determined (held parameter, unknown f0,
// the axis of an insignificant split) is NOT EVALUATED with the reason.
Verdict EvaluateLimits(const LimitsConfig& limits, const estimator::EstimateSummary& estimate,
                       const estimator::EngineeringQuantities& engineering);
// The same with the engineering quantities computed without f0 (a Q limit is then NOT EVALUATED).
Verdict EvaluateLimits(const LimitsConfig& limits, const estimator::EstimateSummary& estimate);

}  // namespace hrgbench::bench
