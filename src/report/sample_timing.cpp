#include "sample_timing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace hrgbench::report {

SampleTiming MeasureSampleTiming(std::span<const double> t_s, double nominal_rate_hz) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  SampleTiming timing{kNaN, kNaN, kNaN, 0};
  if (t_s.size() < 2) return timing;
  std::vector<double> dt(t_s.size() - 1);
  for (std::size_t k = 1; k < t_s.size(); ++k) dt[k - 1] = t_s[k] - t_s[k - 1];
  const double n = static_cast<double>(dt.size());
  double nominal = 0.0;
  if (std::isfinite(nominal_rate_hz) && nominal_rate_hz > 0.0) {
    nominal = 1.0 / nominal_rate_hz;
  } else {
    std::vector<double> sorted = dt;
    const auto middle = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
    std::nth_element(sorted.begin(), middle, sorted.end());
    nominal = *middle;
  }
  double sum = 0.0;
  for (const double step : dt) sum += step;
  const double mean = sum / n;
  double squares = 0.0, worst = 0.0;
  for (const double step : dt) {
    squares += (step - mean) * (step - mean);
    worst = std::max(worst, std::abs(step - nominal));
    if (step > 1.5 * nominal) ++timing.long_steps;
  }
  timing.interval_s = mean;
  timing.jitter_std_s = std::sqrt(squares / n);
  timing.jitter_max_s = worst;
  return timing;
}

}  // namespace hrgbench::report
