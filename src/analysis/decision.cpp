#include "hrgbench/analysis/decision.hpp"

#include <cmath>
#include <cstdio>

namespace hrgbench::bench {
namespace {

std::string Number(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.7g", v);
  return text;
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

std::string_view ToString(DecisionZone zone) noexcept {
  switch (zone) {
    case DecisionZone::kNotJudged:
      return "not_judged";
    case DecisionZone::kConforming:
      return "conforming";
    case DecisionZone::kNonConforming:
      return "non_conforming";
    case DecisionZone::kUndecided:
      return "undecided";
  }
  return "?";
}

Decision Decide(double v, double u, double min, double max, bool guard_min,
                const DecisionRule& rule, const std::string& shown, const std::string& range) {
  Decision d;
  const double k = rule.coverage_factor;
  const bool has_u = std::isfinite(u) && u >= 0.0;
  const double expanded = has_u ? k * u : 0.0;
  const bool guarded = rule.kind != DecisionRuleKind::kSimpleAcceptance;
  if (has_u) {
    d.expanded_uncertainty = expanded;
    d.interval_min = v - expanded;
    d.interval_max = v + expanded;
  }
  d.acceptance_min = guarded && guard_min ? min + expanded : min;
  d.acceptance_max = guarded ? max - expanded : max;
  const std::string with_k = has_u ? " (k = " + Number(k) + ", U = " + Number(expanded) + ")"
                                   : std::string(" (no uncertainty reported: its value judged)");
  // Non-conformance proven: the whole interval beyond a limit. A physical bound is never crossed
  // by the truth, so only a guarded min can be proven violated from below.
  const double beyond_max = (v - expanded) - max;
  const double below_min = min - (v + expanded);
  if (beyond_max > 0.0 || (below_min > 0.0 && (guard_min || !has_u))) {
    d.zone = DecisionZone::kNonConforming;
    d.status = LimitStatus::kFail;
    d.message = shown + " outside " + range +
                (beyond_max > 0.0 ? " (" + Number(v - max) + " above max"
                                  : " (" + Number(min - v) + " below min") +
                (has_u ? ", its whole interval ±" + Number(expanded) + " outside)" : ")") + with_k;
    return d;
  }
  if (!guarded) {
    const double width = max - min;
    if (has_u && expanded > rule.max_uncertainty_ratio * width) {
      d.message = shown + ": not evaluated, too uncertain to judge against " + range +
                  " (U = " + Number(expanded) + " at k = " + Number(k) + " is above " +
                  Number(rule.max_uncertainty_ratio) +
                  " of the limit's width: the sequence does not determine it well enough)";
      return d;
    }
    const bool inside = v >= min && v <= max;
    d.zone = inside ? DecisionZone::kConforming : DecisionZone::kNonConforming;
    d.status = inside ? LimitStatus::kPass : LimitStatus::kFail;
    d.message =
        shown +
        (inside ? " in " + range
                : " outside " + range + " (" +
                      (v > max ? Number(v - max) + " above max" : Number(min - v) + " below min") +
                      ")") +
        " by simple acceptance" + with_k;
    return d;
  }
  if (d.acceptance_min > d.acceptance_max) {
    // 2·U is wider than the tolerance: no value, however central, proves conformance.
    d.message = shown + ": not evaluated, its interval ±" + Number(expanded) +
                " at k = " + Number(k) + " is wider than " + range +
                " allows, so conformance cannot be proven (the sequence does not "
                "determine it well enough)";
    return d;
  }
  if (v >= d.acceptance_min && v <= d.acceptance_max) {
    d.zone = DecisionZone::kConforming;
    d.status = LimitStatus::kPass;
    d.message = shown + " in " + range + with_k;
    return d;
  }
  d.zone = DecisionZone::kUndecided;
  d.status = LimitStatus::kFail;
  d.retest = rule.kind == DecisionRuleKind::kGuardedAcceptanceRetest;
  d.message = shown + " not accepted: its interval [" + Number(v - expanded) + ", " +
              Number(v + expanded) + "] straddles " + range + with_k + ", " +
              (d.retest ? "retest the unit" : "rejected by guarded acceptance");
  return d;
}

}  // namespace hrgbench::bench
