#pragma once
// The verdict: a LimitsConfig applied to an estimate. Each limit is PASS (value in [min, max]),
// FAIL (outside: the unit's fault, STYLE rule 9; the message names the parameter, its value and the
// limit) or NOT EVALUATED (the value does not exist: the estimate is unusable, the parameter was
// held fixed because the sequence cannot determine it, or it is not finite). NOT EVALUATED is not
// a FAIL: the unit was not shown bad, the bench did not measure it; the app reports it as ERROR.
//
// Before any limit, the fit itself is judged (always, with the limits file's [fit] or the
// defaults): per run, the residual ratio, the whiteness of the residuals and the offset of Ω the
// data ask for. A fit outside its model makes every estimated value untrustworthy, so then no
// limit is judged: each becomes NOT EVALUATED (saying what it would have been) and the verdict is
// NOT EVALUATED. A poor fit is never a PASS, and never a FAIL the unit did not earn.
//
// A limit is judged only when the estimate resolves it: its std at most kMaxStdPerLimitWidth of
// the limit's width (max − min), so that a 2σ interval spans at most half the band (a production
// line's usual 4:1 ratio of tolerance to measurement uncertainty). A vaguer estimate is NOT
// EVALUATED ("too uncertain to judge"), unless it lies outside the band by more than
// kConfidentlyOutsideInStd of its std: then it is a FAIL even with its uncertainty. So a short or
// weak sequence can neither pass nor fail a unit on noise.
//
// Pure function of its inputs; thread-safe; allocates (not for real-time code).

#include <string>
#include <string_view>
#include <vector>

#include "hrgbench/config/limits_config.hpp"
#include "hrgbench/estimator/engineering_quantities.hpp"
#include "hrgbench/estimator/summary.hpp"

namespace hrgbench::bench {

enum class LimitStatus { kPass, kFail, kNotEvaluated };

inline constexpr double kMaxStdPerLimitWidth = 0.25;
inline constexpr double kConfidentlyOutsideInStd = 3.0;
std::string_view ToString(LimitStatus status) noexcept;  // "PASS", "FAIL", "NOT EVALUATED"

struct LimitResult {
  LimitedQuantity quantity = LimitedQuantity::kDelta1;
  LimitStatus status = LimitStatus::kNotEvaluated;
  double value = estimator::kNaN;  // the estimate (NaN when there is none)
  double std = estimator::kNaN;    // its standard deviation when the estimator reports one
  double min = estimator::kNaN;
  double max = estimator::kNaN;
  std::string message;  // "delta2 = 0.35 outside [0.29, 0.31] (0.04 above max)", ...
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
