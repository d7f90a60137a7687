#include "hrgbench/bench/verdict.hpp"

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

Value ValueOf(const estimator::EstimateSummary& s, LimitedQuantity q) {
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

LimitResult Evaluate(const ParameterLimit& limit, const estimator::EstimateSummary& estimate) {
  LimitResult result;
  result.quantity = limit.quantity;
  result.min = limit.min;
  result.max = limit.max;
  const std::string name(ToString(limit.quantity));
  const std::string range = "[" + Number(limit.min) + ", " + Number(limit.max) + "]";
  if (!estimate.IsUsable()) {
    result.message = name + ": not evaluated, the estimate is unusable (" +
                     estimator::ToString(estimate.termination) + ")";
    return result;
  }
  const Value v = ValueOf(estimate, limit.quantity);
  result.value = v.value;
  result.std = v.std;
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
  if (v.value < limit.min) {
    result.status = LimitStatus::kFail;
    result.message =
        shown + " outside " + range + " (" + Number(limit.min - v.value) + " below min)";
  } else if (v.value > limit.max) {
    result.status = LimitStatus::kFail;
    result.message =
        shown + " outside " + range + " (" + Number(v.value - limit.max) + " above max)";
  } else {
    result.status = LimitStatus::kPass;
    result.message = shown + " in " + range;
  }
  return result;
}

}  // namespace

std::string_view ToString(LimitStatus status) noexcept {
  switch (status) {
    case LimitStatus::kPass:
      return "PASS";
    case LimitStatus::kFail:
      return "FAIL";
    case LimitStatus::kNotEvaluated:
      return "NOT EVALUATED";
  }
  return "?";
}

std::vector<std::string_view> Verdict::FailedNames() const {
  std::vector<std::string_view> names;
  for (const LimitResult& r : results)
    if (r.status == LimitStatus::kFail) names.push_back(ToString(r.quantity));
  return names;
}

std::string Verdict::Report() const {
  std::string text;
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
  return text + "\n";
}

Verdict EvaluateLimits(const LimitsConfig& limits, const estimator::EstimateSummary& estimate) {
  Verdict verdict;
  bool any_fail = false;
  bool any_not_evaluated = false;
  for (const ParameterLimit& limit : limits.limits) {
    verdict.results.push_back(Evaluate(limit, estimate));
    any_fail = any_fail || verdict.results.back().status == LimitStatus::kFail;
    any_not_evaluated =
        any_not_evaluated || verdict.results.back().status == LimitStatus::kNotEvaluated;
  }
  verdict.overall = any_fail            ? LimitStatus::kFail
                    : any_not_evaluated ? LimitStatus::kNotEvaluated
                                        : LimitStatus::kPass;
  return verdict;
}

}  // namespace hrgbench::bench
