#include "hrgbench/estimator/noise_shape.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>

namespace hrgbench::estimator {
namespace {

// Beyond this |ρ| the declared noise still "remembers" (NoiseMemoryLags).
constexpr double kMemoryThreshold = 0.01;
// ButterworthNoiseShape stops once |ρ| stays below this.
constexpr double kNegligibleRho = 1e-9;

constexpr double kDifference[5] = {1.0, -4.0, 6.0, -4.0, 1.0};

}  // namespace

double NoiseShape::Rho(long lag) const noexcept {
  if (lag < 0) lag = -lag;
  if (IsWhite()) return lag == 0 ? 1.0 : 0.0;
  const auto k = static_cast<std::size_t>(lag);
  return k < autocorrelation.size() ? autocorrelation[k] : 0.0;
}

bool NoiseShape::IsValid(std::string* why) const {
  const auto fail = [why](std::string text) {
    if (why) *why = std::move(text);
    return false;
  };
  if (autocorrelation.size() > kMaxNoiseShapeLags + 1)
    return fail("noise shape: more than " + std::to_string(kMaxNoiseShapeLags) + " lags");
  if (!autocorrelation.empty() && autocorrelation[0] != 1.0)
    return fail("noise shape: the autocorrelation at lag 0 must be 1");
  for (std::size_t k = 0; k < autocorrelation.size(); ++k) {
    if (!std::isfinite(autocorrelation[k]) || std::abs(autocorrelation[k]) > 1.0)
      return fail("noise shape: autocorrelation at lag " + std::to_string(k) +
                  " is not a finite value in [-1, 1]");
  }
  return true;
}

std::optional<NoiseShape> ButterworthNoiseShape(int order, double cutoff_hz,
                                                double sample_rate_hz) {
  if (order < 1 || order > kMaxButterworthOrder || !(cutoff_hz > 0.0) ||
      !std::isfinite(cutoff_hz) || !(sample_rate_hz > 0.0) || !std::isfinite(sample_rate_hz))
    return std::nullopt;
  const double omega_c = 2.0 * std::numbers::pi * cutoff_hz;
  const double dt = 1.0 / sample_rate_hz;
  std::vector<std::complex<double>> poles;
  for (int k = 1; k <= order; ++k) {
    const double angle = std::numbers::pi * (2.0 * k + order - 1) / (2.0 * order);
    poles.push_back(omega_c * std::polar(1.0, angle));
  }
  // R(τ)·2n = Σ −p·e^{p·τ}; the imaginary parts cancel between conjugate poles.
  const auto r = [&poles](double tau) {
    std::complex<double> sum = 0.0;
    for (const std::complex<double>& p : poles) sum -= p * std::exp(p * tau);
    return sum.real();
  };
  const double r0 = r(0.0);
  NoiseShape shape;
  shape.autocorrelation.push_back(1.0);
  // The slowest pole decays as e^{−ω_c·sin(π/2n)·τ}: stop once its envelope is negligible.
  const double decay_per_sample = omega_c * std::sin(std::numbers::pi / (2.0 * order)) * dt;
  for (std::size_t k = 1;; ++k) {
    if (decay_per_sample * static_cast<double>(k) > -std::log(kNegligibleRho) + 10.0) break;
    if (k > kMaxNoiseShapeLags) return std::nullopt;
    shape.autocorrelation.push_back(std::clamp(r(static_cast<double>(k) * dt) / r0, -1.0, 1.0));
  }
  while (shape.autocorrelation.size() > 1 &&
         std::abs(shape.autocorrelation.back()) < kNegligibleRho)
    shape.autocorrelation.pop_back();
  char text[160];
  std::snprintf(text, sizeof text, "Butterworth low-pass, order %d, cutoff %.6g Hz, at %.6g Hz",
                order, cutoff_hz, sample_rate_hz);
  shape.description = text;
  return shape;
}

int NoiseMemoryLags(const NoiseShape& shape) {
  if (shape.IsWhite()) return 1;
  int lags = static_cast<int>(shape.autocorrelation.size());
  while (lags > 1 &&
         std::abs(shape.autocorrelation[static_cast<std::size_t>(lags) - 1]) <= kMemoryThreshold)
    --lags;
  return lags;
}

DifferenceNoiseModel DifferenceNoiseModelFor(const NoiseShape& shape) {
  DifferenceNoiseModel m;
  m.stride = NoiseMemoryLags(shape);
  const long s = m.stride;
  double factor = 0.0;
  for (int j = 0; j < 5; ++j)
    for (int l = 0; l < 5; ++l) factor += kDifference[j] * kDifference[l] * shape.Rho(s * (j - l));
  m.variance_factor = factor;
  // Lags over which any of the three correlations can be non-zero.
  const long reach =
      static_cast<long>(std::max<std::size_t>(shape.autocorrelation.size(), 1)) + 4 * s + 1;
  const double scale = 1.0 / std::sqrt(factor);
  double s_rr = 0.0, s_dd = 0.0, s_rd = 0.0;
  for (long k = -reach; k <= reach; ++k) {
    const double rr = shape.Rho(k);
    double dd = 0.0, rd = 0.0;
    for (int j = 0; j < 5; ++j) {
      rd += kDifference[j] * shape.Rho(k + s * j);
      for (int l = 0; l < 5; ++l)
        dd += kDifference[j] * kDifference[l] * shape.Rho(k + s * (j - l));
    }
    rd *= scale;
    dd /= factor;
    s_rr += rr * rr;
    s_dd += dd * dd;
    s_rd += rd * rd;
  }
  m.ratio_standard_error_scale = std::sqrt(std::max(0.0, (s_rr + s_dd - 2.0 * s_rd) / 8.0));
  return m;
}

WhitenessNull WhitenessNullFor(const NoiseShape& shape, int lags) {
  WhitenessNull null;
  null.first_lag = NoiseMemoryLags(shape);
  null.lags = std::max(1, lags);
  // A[m] = Σ_k ρ_k·ρ_{k+m}: the autocorrelation of the autocorrelation.
  const long reach = static_cast<long>(std::max<std::size_t>(shape.autocorrelation.size(), 1));
  const auto a = [&shape, reach](long m) {
    double sum = 0.0;
    for (long k = -reach; k <= reach; ++k) sum += shape.Rho(k) * shape.Rho(k + m);
    return sum;
  };
  // Per channel: E[Q] = Σ_l (A[0] + A[2l]), Var[Q] = 2·Σ_{l,m} (A[l − m] + A[l + m])².
  double mean = 0.0, variance = 0.0;
  for (int i = 0; i < null.lags; ++i) {
    const long l = null.first_lag + i;
    mean += a(0) + a(2 * l);
    for (int j = 0; j < null.lags; ++j) {
      const long m = null.first_lag + j;
      const double c = a(l - m) + a(l + m);
      variance += 2.0 * c * c;
    }
  }
  mean *= 4.0;  // four independent channels
  variance *= 4.0;
  null.scale = variance / (2.0 * mean);
  null.dof = 2.0 * mean * mean / variance;
  return null;
}

}  // namespace hrgbench::estimator
