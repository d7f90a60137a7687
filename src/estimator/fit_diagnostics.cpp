#include "hrgbench/estimator/fit_diagnostics.hpp"

#include <algorithm>
#include <cmath>

namespace hrgbench::estimator {
namespace {

// 1/Φ⁻¹(3/4): σ = kMadToSigma·median|x| for a zero-mean Gaussian.
constexpr double kMadToSigma = 1.482602218505602;

double MedianOf(std::vector<double>* values) {
  if (values->empty()) return kNaN;
  const auto middle = values->begin() + static_cast<std::ptrdiff_t>(values->size() / 2);
  std::nth_element(values->begin(), middle, values->end());
  return *middle;
}

}  // namespace

bool FitQualityLimits::IsValid(std::string* why) const {
  const auto fail = [why](const char* text) {
    if (why) *why = text;
    return false;
  };
  if (!(residual_ratio_max >= 1.0) || !std::isfinite(residual_ratio_max))
    return fail("residual_ratio_max must be finite and >= 1");
  if (!(whiteness_z_max > 0.0) || !std::isfinite(whiteness_z_max))
    return fail("whiteness_z_max must be finite and > 0");
  if (!(omega_offset_max_in_std > 0.0) || !std::isfinite(omega_offset_max_in_std))
    return fail("omega_offset_max_in_std must be finite and > 0");
  return true;
}

double DifferenceNoiseSigma(const Eigen::Matrix4Xd& y) {
  const Eigen::Index n = y.cols();
  if (n < 5) return kNaN;
  // Δ⁴y_k = y_k − 4y_{k+1} + 6y_{k+2} − 4y_{k+3} + y_{k+4}; its variance is (1+16+36+16+1)·σ² = 70σ².
  std::vector<double> differences;
  differences.reserve(static_cast<std::size_t>(4 * (n - 4)));
  for (Eigen::Index k = 0; k + 4 < n; ++k) {
    const Eigen::Vector4d d = y.col(k) - 4.0 * y.col(k + 1) + 6.0 * y.col(k + 2) -
                              4.0 * y.col(k + 3) + y.col(k + 4);
    for (int c = 0; c < 4; ++c) differences.push_back(d[c]);
  }
  // A robust scale first (the median of |Δ⁴y|), then the mean square of the differences within
  // kTrim of it: as efficient as the plain mean square on Gaussian noise (the trimmed share is
  // ~1e-9), and a spike only touches the differences it is in.
  std::vector<double> magnitudes(differences.size());
  for (std::size_t i = 0; i < differences.size(); ++i) magnitudes[i] = std::abs(differences[i]);
  const double robust = kMadToSigma * MedianOf(&magnitudes);
  constexpr double kTrim = 6.0;
  double sum2 = 0.0;
  std::size_t kept = 0;
  for (double d : differences) {
    if (robust > 0.0 && std::abs(d) > kTrim * robust) continue;
    sum2 += d * d;
    ++kept;
  }
  if (kept == 0) return 0.0;
  return std::sqrt(sum2 / static_cast<double>(kept) / 70.0);
}

double ResidualRatioThreshold(const FitQualityLimits& limits, std::size_t samples) {
  if (samples == 0) return limits.residual_ratio_max;
  return std::max(limits.residual_ratio_max,
                  1.0 + 5.0 * kResidualRatioStandardErrorScale /
                            std::sqrt(static_cast<double>(samples)));
}

double ChiSquareNormalScore(double q, double dof) {
  if (!(dof > 0.0) || !std::isfinite(q)) return kNaN;
  const double v = 2.0 / (9.0 * dof);
  return (std::cbrt(q / dof) - (1.0 - v)) / std::sqrt(v);
}

ResidualStatistics AnalyseResiduals(const Eigen::Matrix4Xd& residuals, int lags) {
  ResidualStatistics s;
  const Eigen::Index n = residuals.cols();
  if (n < 8) return s;
  const double count = static_cast<double>(4 * n);
  s.rms = std::sqrt(residuals.squaredNorm() / count);
  std::vector<double> magnitudes(static_cast<std::size_t>(4 * n));
  Eigen::Map<Eigen::ArrayXd>(magnitudes.data(), 4 * n) =
      Eigen::Map<const Eigen::ArrayXd>(residuals.data(), 4 * n).abs();
  const double largest = *std::max_element(magnitudes.begin(), magnitudes.end());
  s.robust_sigma = kMadToSigma * MedianOf(&magnitudes);
  s.max_abs_in_sigma = s.robust_sigma > 0.0 ? largest / s.robust_sigma : kNaN;
  const double m2 = s.rms * s.rms;
  const double m4 = Eigen::Map<const Eigen::ArrayXd>(residuals.data(), 4 * n).square().square().sum() /
                    count;
  s.excess_kurtosis = m2 > 0.0 ? m4 / (m2 * m2) - 3.0 : kNaN;

  s.lags = static_cast<int>(std::clamp<Eigen::Index>(lags, 1, std::max<Eigen::Index>(1, n / 4)));
  const auto nd = static_cast<double>(n);
  double q = 0.0;
  double rho1_sum = 0.0;
  Eigen::VectorXd rho_sum = Eigen::VectorXd::Zero(s.lags);
  for (int c = 0; c < 4; ++c) {
    const Eigen::VectorXd r = residuals.row(c).transpose();
    const double c0 = r.squaredNorm();
    if (!(c0 > 0.0)) continue;
    for (int l = 1; l <= s.lags; ++l) {
      const double rho = r.head(n - l).dot(r.tail(n - l)) / c0;
      q += nd * (nd + 2.0) * rho * rho / (nd - l);
      rho_sum[l - 1] += 0.25 * rho;
    }
    rho1_sum += 0.25 * r.head(n - 1).dot(r.tail(n - 1)) / c0;
  }
  s.ljung_box_q = q;
  s.ljung_box_z = ChiSquareNormalScore(q, 4.0 * s.lags);
  s.lag1_autocorrelation = rho1_sum;
  // Integrated correlation with a Bartlett taper, so noise in the far lags does not dominate.
  double integrated = 1.0;
  for (int l = 1; l <= s.lags; ++l)
    integrated += 2.0 * (1.0 - static_cast<double>(l) / (s.lags + 1)) * rho_sum[l - 1];
  s.integrated_correlation_samples = std::max(1.0, integrated);
  return s;
}

}  // namespace hrgbench::estimator
