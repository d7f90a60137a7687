#pragma once
// Line statistics of one parameter over sessions (hrg-results stats): n, mean, sample std, min,
// max, the yield and the first-pass yield against the limits in force, the process capability,
// and a per-ISO-week trend (n, mean, std per week). GroupSamples splits the samples by sequence,
// limits or product first (stats --by), so that sessions of different plans are not pooled.
//
// The limits in force are those of the newest session (by start time) that judged the parameter:
// a line changes its limits file, and yesterday's limits say nothing about today's. Yield is the
// share of the sessions that judged the parameter whose verdict on it was PASS; the first-pass
// yield the same over the unit's first sessions with their sequence only (attempt 1: a retest
// that passes does not raise it).
//
// Capability (ISO 22514-2), with σ > 0: Cpu = (USL - μ) / 3σ, Cpl = (μ - LSL) / 3σ. A two-sided
// limit gives Cp = (USL - LSL) / 6σ and Cpk = min(Cpu, Cpl); a one-sided one only its own side
// (Cpu or Cpl; Cp and Cpk are not defined). A magnitude limited [0, max] (lower limit 0 and no
// value below it: a split, an RMS) is one-sided: 0 is the quantity's natural bound, not a
// specification limit, and a two-sided Cpk would report the distance to it as a process fault.
//
// Pure computation on the samples given; thread-safe; never throws (except std::bad_alloc).

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
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
  std::size_t first_pass_judged = 0, first_pass_passed = 0;  // the same over attempt 1 only
  std::optional<double> first_pass_yield;
  // "Cpk" (two-sided), "Cpu" or "Cpl" (one-sided): the index that applies; "" when none does
  // (no limit in force, or σ = 0).
  std::string capability;
  std::optional<double> cp, cpk, cpu, cpl;
  std::vector<WeekStats> weeks;  // oldest first
};

ParameterStats ComputeParameterStats(const std::string& name,
                                     const std::vector<ParameterSample>& samples);

// What stats --by groups on.
enum class GroupBy { kSequence, kLimits, kProduct };
// "sequence", "limits", "product"; nullopt for anything else.
std::optional<GroupBy> ParseGroupBy(std::string_view text);
const char* ToString(GroupBy by);

struct SampleGroup {
  std::vector<std::string> key;  // one value per GroupBy given, in that order ("" when none)
  std::vector<ParameterSample> samples;
};
// The samples split by the values of `by` (all in one group when `by` is empty), groups sorted by
// key, samples in the order given.
std::vector<SampleGroup> GroupSamples(const std::vector<ParameterSample>& samples,
                                      const std::vector<GroupBy>& by);

// "2026-W48" for an ISO 8601 date-time text ("2026-11-23T..."); "" when it does not start with a
// valid YYYY-MM-DD.
std::string IsoWeek(const std::string& utc);

}  // namespace hrgbench::results
