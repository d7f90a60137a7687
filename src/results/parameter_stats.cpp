#include "hrgbench/results/parameter_stats.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>

namespace hrgbench::results {
namespace {

// Welford's running mean and variance: stable for 1e5 values of a parameter near 1e-9 ± 1e-12.
struct Running {
  std::size_t n = 0;
  double mean = 0.0, m2 = 0.0;
  void Add(double x) {
    ++n;
    const double d = x - mean;
    mean += d / static_cast<double>(n);
    m2 += d * (x - mean);
  }
  double Std() const { return n > 1 ? std::sqrt(m2 / static_cast<double>(n - 1)) : 0.0; }
};

}  // namespace

std::string IsoWeek(const std::string& utc) {
  int y = 0;
  unsigned m = 0, d = 0;
  if (utc.size() < 10 || std::sscanf(utc.c_str(), "%4d-%2u-%2u", &y, &m, &d) != 3) return "";
  using namespace std::chrono;
  const year_month_day ymd{year{y}, month{m}, day{d}};
  if (!ymd.ok()) return "";
  const sys_days date{ymd};
  // The ISO week belongs to the year of its Thursday.
  const weekday wd{date};
  const int iso_wd = wd.iso_encoding();  // Monday = 1
  const sys_days thursday = date + days{4 - iso_wd};
  const year_month_day thu{thursday};
  const sys_days jan1{thu.year() / January / 1};
  const int week = static_cast<int>((thursday - jan1).count() / 7 + 1);
  char text[32];
  std::snprintf(text, sizeof text, "%04d-W%02d", static_cast<int>(thu.year()), week);
  return text;
}

ParameterStats ComputeParameterStats(const std::string& name,
                                     const std::vector<ParameterSample>& samples) {
  ParameterStats stats;
  stats.name = name;
  Running all;
  std::map<std::string, Running> weeks;
  std::string newest_judged;
  for (const ParameterSample& s : samples) {
    if (stats.unit.empty()) stats.unit = s.unit;
    if (all.n == 0) stats.min = stats.max = s.value;
    stats.min = std::min(stats.min, s.value);
    stats.max = std::max(stats.max, s.value);
    all.Add(s.value);
    weeks[IsoWeek(s.started_utc)].Add(s.value);
    if (s.limit_status == "PASS" || s.limit_status == "FAIL") {
      ++stats.judged;
      if (s.limit_status == "PASS") ++stats.passed;
      if (s.attempt == 1) {
        ++stats.first_pass_judged;
        if (s.limit_status == "PASS") ++stats.first_pass_passed;
      }
      if (s.started_utc >= newest_judged) {
        newest_judged = s.started_utc;
        stats.limit_min = s.limit_min;
        stats.limit_max = s.limit_max;
      }
    }
  }
  stats.n = all.n;
  stats.mean = all.mean;
  stats.std = all.Std();
  if (stats.judged > 0)
    stats.yield = static_cast<double>(stats.passed) / static_cast<double>(stats.judged);
  if (stats.first_pass_judged > 0) {
    stats.first_pass_yield =
        static_cast<double>(stats.first_pass_passed) / static_cast<double>(stats.first_pass_judged);
  }
  if (stats.std > 0.0) {
    const double sigma = stats.std;
    // A lower limit at the natural zero of a magnitude is no specification limit (header).
    const bool natural_zero = stats.limit_min && *stats.limit_min == 0.0 && stats.min >= 0.0;
    const bool has_lower = stats.limit_min.has_value() && !natural_zero;
    const double lower = has_lower ? *stats.limit_min : 0.0;
    if (stats.limit_max) stats.cpu = (*stats.limit_max - stats.mean) / (3.0 * sigma);
    if (has_lower) stats.cpl = (stats.mean - lower) / (3.0 * sigma);
    if (stats.cpu && stats.cpl) {
      stats.cp = (stats.limit_max.value_or(0.0) - lower) / (6.0 * sigma);
      stats.cpk = std::min(*stats.cpu, *stats.cpl);
      stats.capability = "Cpk";
    } else if (stats.cpu) {
      stats.capability = "Cpu";
    } else if (stats.cpl) {
      stats.capability = "Cpl";
    }
  }
  for (const auto& [week, r] : weeks) stats.weeks.push_back({week, r.n, r.mean, r.Std()});
  return stats;
}

std::optional<GroupBy> ParseGroupBy(std::string_view text) {
  if (text == "sequence") return GroupBy::kSequence;
  if (text == "limits") return GroupBy::kLimits;
  if (text == "product") return GroupBy::kProduct;
  return std::nullopt;
}

const char* ToString(GroupBy by) {
  switch (by) {
    case GroupBy::kSequence:
      return "sequence";
    case GroupBy::kLimits:
      return "limits";
    case GroupBy::kProduct:
      return "product";
  }
  return "?";
}

std::vector<SampleGroup> GroupSamples(const std::vector<ParameterSample>& samples,
                                      const std::vector<GroupBy>& by) {
  std::map<std::vector<std::string>, std::vector<ParameterSample>> groups;
  for (const ParameterSample& s : samples) {
    std::vector<std::string> key;
    for (GroupBy b : by) {
      key.push_back(b == GroupBy::kSequence ? s.sequence_name
                    : b == GroupBy::kLimits ? s.limits_name
                                            : s.product);
    }
    groups[std::move(key)].push_back(s);
  }
  std::vector<SampleGroup> out;
  for (auto& [key, members] : groups) out.push_back({key, std::move(members)});
  return out;
}

}  // namespace hrgbench::results
