#pragma once
// Line statistics of one parameter over sessions (hrg-results stats): n, mean, sample std, min,
// max, the yield against the limits in force, the process capability Cp = (USL - LSL) / 6σ and
// Cpk = min(USL - μ, μ - LSL) / 3σ, and a per-ISO-week trend (n, mean, std per week).
//
// The limits in force are those of the newest session (by start time) that judged the parameter:
// a line changes its limits file, and yesterday's limits say nothing about today's. Yield is the
// share of the sessions that judged the parameter whose verdict on it was PASS. Cp/Cpk need both
// limits and σ > 0 (nullopt otherwise; Cpk with one limit uses that side only).
//
// Pure computation on the samples given; thread-safe; never throws (except std::bad_alloc).

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "hrgbench/results/results_store.hpp"

namespace hrgbench::results {

struct WeekStats {
  std::string week;  // ISO 8601 week, "2026-W48"
  std::size_t n = 0;
  double mean = 0.0;
  double std = 0.0;  // sample std (n - 1); 0 for n = 1
};

struct ParameterStats {
  std::string name;
  std::string unit;
  std::size_t n = 0;
  double mean = 0.0, std = 0.0, min = 0.0, max = 0.0;
  std::optional<double> limit_min, limit_max;  // in force (see above)
  std::size_t judged = 0, passed = 0;          // sessions with a verdict on it, of which PASS
  std::optional<double> yield;                 // passed / judged
  std::optional<double> cp, cpk;
  std::vector<WeekStats> weeks;  // oldest first
};

ParameterStats ComputeParameterStats(const std::string& name,
                                     const std::vector<ParameterSample>& samples);

// "2026-W48" for an ISO 8601 date-time text ("2026-11-23T..."); "" when it does not start with a
// valid YYYY-MM-DD.
std::string IsoWeek(const std::string& utc);

}  // namespace hrgbench::results
