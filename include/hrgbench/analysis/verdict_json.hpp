#pragma once
// The verdict as the session record and `--json` carry it (session.json outcome.verdict):
//
//   overall         "PASS" | "FAIL" | "NOT EVALUATED"
//   fit_acceptable  bool
//   fit_checks      [{run, name, status, value, max, message}]
//   limits          [{quantity, status, value, std, min, max, message}] in the limits file's order
//
// Every non-finite number is null. Pure function; allocates.

#include <nlohmann/json.hpp>

#include "hrgbench/analysis/verdict.hpp"

namespace hrgbench::bench {

nlohmann::json VerdictJson(const Verdict& verdict);

}  // namespace hrgbench::bench
