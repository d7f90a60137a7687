#pragma once
// The verdict as the session record and `--json` carry it (session.json outcome.verdict):
//
//   overall         "PASS" | "FAIL" | "NOT EVALUATED"
//   fit_acceptable  bool
//   fit_checks      [{run, name, status, value, max, message}]
//   limits          [{quantity, status, value, std, min, max, message, rule, zone,
//                   coverage_factor, expanded_uncertainty, interval_min, interval_max,
//                   acceptance_min, acceptance_max, retest}] in the limits file's order
//                   (verdict.hpp: zone "conforming" | "non_conforming" | "undecided" |
//                   "not_judged")
//   decision        {rule, coverage_factor[, max_uncertainty_ratio]} (config/decision_rule.hpp)
//   retest          bool: the FAIL is undecided limits only, under guarded_acceptance_retest
//
// Every non-finite number is null. Pure function; allocates.

#include <nlohmann/json.hpp>

#include "hrgbench/analysis/verdict.hpp"

namespace hrgbench::bench {

nlohmann::json VerdictJson(const Verdict& verdict);

}  // namespace hrgbench::bench
