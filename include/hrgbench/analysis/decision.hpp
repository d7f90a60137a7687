#pragma once
// One value with its standard uncertainty judged against [min, max] under a limits file's decision
// rule (config/decision_rule.hpp: guarded acceptance or simple acceptance, k, U = k·u). The one
// place the rule is applied: the session's limits (verdict.hpp) and the tuning's (bench/tuning)
// both decide through it, so the guard band means the same wherever a limit is judged.
//
// Pure; allocates its message.

#include <limits>
#include <string>
#include <string_view>

#include "hrgbench/config/decision_rule.hpp"

namespace hrgbench::bench {

enum class LimitStatus { kPass, kFail, kNotEvaluated };

std::string_view ToString(LimitStatus status) noexcept;  // "PASS", "FAIL", "NOT EVALUATED"

// Where the value's expanded interval lies against the limit (JCGM 106 §8).
enum class DecisionZone { kNotJudged, kConforming, kNonConforming, kUndecided };
// "not_judged", "conforming", "non_conforming", "undecided": the record's spelling.
std::string_view ToString(DecisionZone zone) noexcept;

struct Decision {
  LimitStatus status = LimitStatus::kNotEvaluated;
  DecisionZone zone = DecisionZone::kNotJudged;
  double expanded_uncertainty = std::numeric_limits<double>::quiet_NaN();  // U = k·u
  double interval_min = std::numeric_limits<double>::quiet_NaN();          // v − U
  double interval_max = std::numeric_limits<double>::quiet_NaN();          // v + U
  // The acceptance zone: [min + U, max − U] under a guarded rule (min itself when the low side is
  // not guarded), [min, max] under simple acceptance.
  double acceptance_min = std::numeric_limits<double>::quiet_NaN();
  double acceptance_max = std::numeric_limits<double>::quiet_NaN();
  bool retest = false;  // undecided under guarded_acceptance_retest
  std::string message;  // "<shown> in <range> (k = 2, U = …)", "… outside …", "… not accepted …"
};

// v (finite) with standard uncertainty u (NaN: none reported, the value is judged on its own and
// the message says so) against [min, max]. `guard_min`: the low side is a tolerance (false when
// min is the quantity's physical bound, e.g. a magnitude's 0, which no unit is beyond). `shown`
// names the value in the message ("delta2 = 0.35"), `range` the limit ("[0.29, 0.31]").
Decision Decide(double v, double u, double min, double max, bool guard_min,
                const DecisionRule& rule, const std::string& shown, const std::string& range);

}  // namespace hrgbench::bench
