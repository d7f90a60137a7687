#include "hrgbench/analysis/allan_deviation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hrgbench::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The regularised lower incomplete gamma function P(a, x) = γ(a, x) / Γ(a): its power series
// below x = a + 1, else 1 − Q(a, x) from Q's continued fraction (modified Lentz), each to double
// precision (the two converge fastest on those sides).
double RegularizedGammaP(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double log_prefix = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 10000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-16) break;
    }
    return std::min(1.0, sum * std::exp(log_prefix));
  }
  constexpr double kTiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double step = d * c;
    h *= step;
    if (std::abs(step - 1.0) < 1e-16) break;
  }
  return std::max(0.0, 1.0 - std::exp(log_prefix) * h);
}

double ChiSquaredCdf(double x, double dof) { return RegularizedGammaP(0.5 * dof, 0.5 * x); }

}  // namespace

double ChiSquaredQuantile(double p, double dof) {
  if (!(p > 0.0 && p < 1.0) || !(dof > 0.0) || !std::isfinite(dof)) return kNaN;
  // Bracket, then bisect on log x (the CDF is monotone; quantiles span many decades at small dof).
  double lo = 1e-300, hi = std::max(1.0, dof);
  while (ChiSquaredCdf(hi, dof) < p) hi *= 2.0;
  double log_lo = std::log(lo), log_hi = std::log(hi);
  for (int i = 0; i < 200 && log_hi - log_lo > 1e-15; ++i) {
    const double mid = 0.5 * (log_lo + log_hi);
    (ChiSquaredCdf(std::exp(mid), dof) < p ? log_lo : log_hi) = mid;
  }
  return std::exp(0.5 * (log_lo + log_hi));
}

double OverlappingAllanEdf(RateNoise noise, std::size_t samples, int m) {
  // N: the angle points the rate samples span (SP 1065 counts phase data).
  const double n = static_cast<double>(samples) + 1.0;
  const double mm = m;
  switch (noise) {
    case RateNoise::kWhiteAngle:
      return (n + 1.0) * (n - 2.0 * mm) / (2.0 * (n - mm));
    case RateNoise::kFlickerAngle:
      return std::exp(std::sqrt(std::log((n - 1.0) / (2.0 * mm)) *
                                std::log((2.0 * mm + 1.0) * (n - 1.0) / 4.0)));
    case RateNoise::kWhiteRate:
      return (3.0 * (n - 1.0) / (2.0 * mm) - 2.0 * (n - 2.0) / n) * 4.0 * mm * mm /
             (4.0 * mm * mm + 5.0);
    case RateNoise::kFlickerRate:
      return m == 1 ? 2.0 * (n - 2.0) / (2.3 * n - 4.9) : 5.0 * n * n / (4.0 * mm * (n + 3.0 * mm));
    case RateNoise::kRateRandomWalk:
      return (n - 2.0) / mm * ((n - 1.0) * (n - 1.0) - 3.0 * mm * (n - 1.0) + 4.0 * mm * mm) /
             ((n - 3.0) * (n - 3.0));
  }
  return kNaN;
}

std::vector<int> OctaveFactors(std::size_t samples, std::size_t min_differences) {
  std::vector<int> factors;
  for (std::size_t m = 1;
       2 * m <= samples && samples - 2 * m + 1 >= std::max<std::size_t>(min_differences, 1); m *= 2)
    factors.push_back(static_cast<int>(m));
  return factors;
}

std::vector<AllanPoint> OverlappingAllanDeviation(std::span<const double> rate, double tau0_s,
                                                  std::span<const int> m, RateNoise dominant,
                                                  double confidence) {
  std::vector<AllanPoint> points;
  const std::size_t count = rate.size();
  if (count < 3 || !(tau0_s > 0.0) || !(confidence > 0.0 && confidence < 1.0)) return points;
  // The angle in units of τ0, A_i = Σ_{k<i} y_k (A_0 = 0): ȳ_{j+m} − ȳ_j = (A_{j+2m} − 2 A_{j+m} +
  // A_j) / m, one pass per τ instead of m additions per difference. Summed in long double: the
  // angle grows with the bias while its second differences stay small.
  std::vector<long double> angle(count + 1, 0.0L);
  for (std::size_t i = 0; i < count; ++i) {
    if (!std::isfinite(rate[i])) return {};
    angle[i + 1] = angle[i] + static_cast<long double>(rate[i]);
  }
  const double lower_p = 0.5 * (1.0 - confidence);
  for (const int factor : m) {
    if (factor < 1 || 2 * static_cast<std::size_t>(factor) >= count + 1) continue;
    const auto step = static_cast<std::size_t>(factor);
    const std::size_t differences = count - 2 * step + 1;
    long double sum = 0.0L;
    for (std::size_t j = 0; j < differences; ++j) {
      const long double d = angle[j + 2 * step] - 2.0L * angle[j + step] + angle[j];
      sum += d * d;
    }
    const double variance = static_cast<double>(
        sum / (2.0L * static_cast<long double>(differences) * static_cast<long double>(step) *
               static_cast<long double>(step)));
    AllanPoint point;
    point.m = factor;
    point.tau_s = factor * tau0_s;
    point.deviation = std::sqrt(variance);
    point.edf = std::max(1.0, OverlappingAllanEdf(dominant, count, factor));
    point.lower = std::sqrt(variance * point.edf / ChiSquaredQuantile(1.0 - lower_p, point.edf));
    point.upper = std::sqrt(variance * point.edf / ChiSquaredQuantile(lower_p, point.edf));
    points.push_back(point);
  }
  return points;
}

}  // namespace hrgbench::analysis
