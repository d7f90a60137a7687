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
  if (stats.std > 0.0) {
    const double sigma = stats.std;
    if (stats.limit_min && stats.limit_max) {
      stats.cp = (*stats.limit_max - *stats.limit_min) / (6.0 * sigma);
      stats.cpk =
          std::min(*stats.limit_max - stats.mean, stats.mean - *stats.limit_min) / (3.0 * sigma);
    } else if (stats.limit_max) {
      stats.cpk = (*stats.limit_max - stats.mean) / (3.0 * sigma);
    } else if (stats.limit_min) {
      stats.cpk = (stats.mean - *stats.limit_min) / (3.0 * sigma);
    }
  }
  for (const auto& [week, r] : weeks) stats.weeks.push_back({week, r.n, r.mean, r.Std()});
  return stats;
}

}  // namespace hrgbench::results
