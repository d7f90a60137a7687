#pragma once
// The decision rule of a limits file ([decision]): how a measured value with its uncertainty is
// turned into accept or reject against a limit (JCGM 106:2012 §8, ISO 14253-1:2017). The value v
// carries its combined standard uncertainty u (the estimate's std; for an engineering quantity
// u_c, estimator/engineering_quantities.hpp) and the file's coverage factor k gives the expanded
// uncertainty U = k·u.
//
// Guarded acceptance (the two guarded rules): the acceptance zone is the tolerance interval
// shrunk by U at each guarded side, [min + U, max − U]. So
//   conforming      [v − U, v + U] inside [min, max]          PASS
//   non-conforming  [v − U, v + U] wholly outside [min, max]  FAIL
//   undecided       in between                                not accepted: the rule says what
//                                                             then (retest the unit, or reject it)
// A side whose limit is the quantity's physical bound (a magnitude's min = 0: it cannot be below
// it; LimitsConfig's PhysicalMinimum) is not guarded: no unit is on the wrong side of it, so a
// guard there would only reject good units whose interval reaches past the bound.
//
// Simple acceptance (ISO 14253-1's "simple acceptance", ILAC-G8 §4.2.1): the point value decides,
// provided U is at most `max_uncertainty_ratio` of the tolerance width T = max − min; a value with
// a larger U cannot be judged (NOT EVALUATED) unless its whole interval is outside (FAIL).
//
// Plain data; thread-compatible.

#include <array>
#include <cstddef>
#include <optional>
#include <string_view>

namespace hrgbench::bench {

enum class DecisionRuleKind {
  kGuardedAcceptanceRetest,  // undecided: not accepted, the unit is measured again (retest)
  kGuardedAcceptanceReject,  // undecided: not accepted, the unit is rejected
  kSimpleAcceptance,         // the point value, with U/T at most max_uncertainty_ratio
};
inline constexpr std::array<std::string_view, 3> kDecisionRuleNames = {
    "guarded_acceptance_retest", "guarded_acceptance_reject", "simple_acceptance"};

constexpr std::string_view ToString(DecisionRuleKind kind) noexcept {
  const auto index = static_cast<std::size_t>(kind);
  return index < kDecisionRuleNames.size() ? kDecisionRuleNames[index] : "?";
}
constexpr std::optional<DecisionRuleKind> ParseDecisionRuleKind(std::string_view text) noexcept {
  for (std::size_t i = 0; i < kDecisionRuleNames.size(); ++i)
    if (text == kDecisionRuleNames[i]) return static_cast<DecisionRuleKind>(i);
  return std::nullopt;
}

// Bounds the loader enforces: k below 1 is less than one standard uncertainty (no guard a
// metrologist would call one), above 6 no sequence could ever prove conformance.
inline constexpr double kMinCoverageFactor = 1.0;
inline constexpr double kMaxCoverageFactor = 6.0;

struct DecisionRule {
  // The default when a limits file has no [decision]: a point value is never accepted on its own
  // (issue 26: a good unit FAILed, and a marginal one could PASS, on the noise of a short
  // sequence).
  DecisionRuleKind kind = DecisionRuleKind::kGuardedAcceptanceRetest;
  double coverage_factor = 2.0;  // k of U = k·u (about 95 % for a normal distribution)
  // Simple acceptance only: the largest U / (max − min) a point value may be judged with. 0.5
  // is the bench's rule before [decision] (std ≤ a quarter of the width at k = 2).
  double max_uncertainty_ratio = 0.25;
  std::size_t line = 0;  // where [decision] was written; 0 = not in the file (defaults)
};

}  // namespace hrgbench::bench
