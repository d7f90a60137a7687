#pragma once
// The verdict: a LimitsConfig applied to an estimate. Each limit is PASS (value in [min, max]),
// FAIL (outside: the unit's fault, STYLE rule 9; the message names the parameter, its value and the
// limit) or NOT EVALUATED (the value does not exist: the estimate is unusable, the parameter was
// held fixed because the sequence cannot determine it, or it is not finite). NOT EVALUATED is not
// a FAIL: the unit was not shown bad, the bench did not measure it; the app reports it as ERROR.
//
// Pure function of its inputs; thread-safe; allocates (not for real-time code).

#include <string>
#include <string_view>
#include <vector>

#include "hrgbench/bench/limits_config.hpp"
#include "hrgbench/estimator/summary.hpp"

namespace hrgbench::bench {

enum class LimitStatus { kPass, kFail, kNotEvaluated };
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

struct Verdict {
  // kFail if any limit failed; else kNotEvaluated if any could not be evaluated; else kPass (also
  // when there are no limits: nothing was required).
  LimitStatus overall = LimitStatus::kPass;
  std::vector<LimitResult> results;  // one per limit, in the limits file's order

  std::vector<std::string_view> FailedNames() const;
  // One line per limit ("FAIL  delta2 = ..."), then "verdict: FAIL (delta2)".
  std::string Report() const;
};

Verdict EvaluateLimits(const LimitsConfig& limits, const estimator::EstimateSummary& estimate);

}  // namespace hrgbench::bench
