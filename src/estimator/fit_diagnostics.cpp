#include "hrgbench/estimator/fit_diagnostics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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

// |x| of every value, or of an evenly strided subset of kMedianSubset of them.
constexpr std::size_t kMedianSubset = std::size_t{1} << 16;

double RobustSigmaOf(const double* data, std::size_t count) {
  if (count == 0) return kNaN;
  const std::size_t stride = std::max<std::size_t>(1, count / kMedianSubset);
  std::vector<double> magnitudes;
  magnitudes.reserve(count / stride + 1);
  for (std::size_t i = 0; i < count; i += stride) magnitudes.push_back(std::abs(data[i]));
  return kMadToSigma * MedianOf(&magnitudes);
}

}  // namespace

double RobustSigma(const Eigen::Matrix4Xd& values) {
  return RobustSigmaOf(values.data(), static_cast<std::size_t>(values.size()));
}

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

double DifferenceNoiseSigma(const Eigen::Matrix4Xd& y) { return DifferenceNoiseSigma(y, {}); }

double DifferenceNoiseSigma(const Eigen::Matrix4Xd& y, const DifferenceNoiseModel& model) {
  const Eigen::Index n = y.cols();
  const Eigen::Index s = std::max(1, model.stride);
  if (n < 4 * s + 1) return kNaN;
  // Δ⁴y_k = y_k − 4y_{k+s} + 6y_{k+2s} − 4y_{k+3s} + y_{k+4s}; its variance is
  // (1+16+36+16+1)·σ² = 70σ² for white noise, variance_factor·σ² for the declared shape.
  const auto difference = [&y, s](Eigen::Index k) -> Eigen::Vector4d {
    return y.col(k) - 4.0 * y.col(k + s) + 6.0 * y.col(k + 2 * s) - 4.0 * y.col(k + 3 * s) +
           y.col(k + 4 * s);
  };
  const auto count = static_cast<std::size_t>(n - 4 * s);
  // A robust scale first (the median of |Δ⁴y| over at most 2^16 strided differences), then the mean
  // square of the differences within kTrim of it: as efficient as the plain mean square on Gaussian
  // noise (the trimmed share is ~1e-9), and a spike only touches the differences it is in. Two
  // passes, nothing stored per sample.
  const std::size_t stride = std::max<std::size_t>(1, 4 * count / kMedianSubset);
  std::vector<double> magnitudes;
  magnitudes.reserve(count / stride + 1);
  for (std::size_t k = 0; k < count; k += stride)
    for (const double d : difference(static_cast<Eigen::Index>(k)))
      magnitudes.push_back(std::abs(d));
  const double robust = kMadToSigma * MedianOf(&magnitudes);
  constexpr double kTrim = 6.0;
  const double limit = robust > 0.0 ? kTrim * robust : std::numeric_limits<double>::infinity();
  double sum2 = 0.0;
  std::size_t kept = 0;
  for (Eigen::Index k = 0; k + 4 * s < n; ++k) {
    for (const double d : difference(k)) {
      if (std::abs(d) > limit) continue;
      sum2 += d * d;
      ++kept;
    }
  }
  if (kept == 0) return 0.0;
  return std::sqrt(sum2 / static_cast<double>(kept) / model.variance_factor);
}

double ResidualRatioThreshold(const FitQualityLimits& limits, std::size_t samples,
                              double standard_error_scale) {
  if (samples == 0) return limits.residual_ratio_max;
  return std::max(limits.residual_ratio_max,
                  1.0 + 5.0 * standard_error_scale / std::sqrt(static_cast<double>(samples)));
}

double ChiSquareNormalScore(double q, double dof) {
  if (!(dof > 0.0) || !std::isfinite(q)) return kNaN;
  const double v = 2.0 / (9.0 * dof);
  return (std::cbrt(q / dof) - (1.0 - v)) / std::sqrt(v);
}

ResidualStatistics AnalyseResiduals(const Eigen::Matrix4Xd& residuals, int lags) {
  WhitenessNull white;
  white.lags = std::max(1, lags);
  white.dof = 4.0 * white.lags;
  return AnalyseResiduals(residuals, white);
}

ResidualStatistics AnalyseResiduals(const Eigen::Matrix4Xd& residuals, const WhitenessNull& null) {
  ResidualStatistics s;
  const Eigen::Index n = residuals.cols();
  if (n < 8) return s;
  const double count = static_cast<double>(4 * n);
  s.robust_sigma = RobustSigma(residuals);

  // Lags first_lag … first_lag + L − 1 are judged; every lag from 1 on enters the integrated
  // correlation (the sandwich's batch length), the declared noise's memory included.
  const Eigen::Index first = std::max(1, null.first_lag);
  s.lags = static_cast<int>(
      std::clamp<Eigen::Index>(null.lags, 1, std::max<Eigen::Index>(1, n / 4 - first + 1)));
  const Eigen::Index last = first + s.lags - 1;
  const auto nd = static_cast<double>(n);
  double q = 0.0;
  double rho1_sum = 0.0;
  Eigen::VectorXd rho_sum = Eigen::VectorXd::Zero(last);
  // Every moment and every lag's products of all four channels in one pass over the columns (the
  // residuals are stored column-major: one sample's four channels are adjacent), instead of a pass
  // per statistic, channel and lag.
  Eigen::Matrix4Xd lagged = Eigen::Matrix4Xd::Zero(4, last);
  Eigen::Array4d c0 = Eigen::Array4d::Zero();  // per channel Σ r²
  double sum4 = 0.0;                           // Σ r⁴
  double largest = 0.0;                        // max |r|
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Array4d x = residuals.col(k).array();
    const Eigen::Array4d x2 = x * x;
    c0 += x2;
    sum4 += (x2 * x2).sum();
    largest = std::max(largest, x.abs().maxCoeff());
    const Eigen::Index top = std::min<Eigen::Index>(last, k);
    for (Eigen::Index l = 1; l <= top; ++l)
      lagged.col(l - 1) += residuals.col(k).cwiseProduct(residuals.col(k - l));
  }
  s.rms = std::sqrt(c0.sum() / count);
  s.max_abs_in_sigma = s.robust_sigma > 0.0 ? largest / s.robust_sigma : kNaN;
  const double m2 = s.rms * s.rms;
  const double m4 = sum4 / count;
  s.excess_kurtosis = m2 > 0.0 ? m4 / (m2 * m2) - 3.0 : kNaN;
  for (int c = 0; c < 4; ++c) {
    if (!(c0[c] > 0.0)) continue;
    for (Eigen::Index l = 1; l <= last; ++l) {
      const double rho = lagged(c, l - 1) / c0[c];
      if (l >= first) q += nd * (nd + 2.0) * rho * rho / (nd - static_cast<double>(l));
      rho_sum[l - 1] += 0.25 * rho;
    }
    rho1_sum += 0.25 * lagged(c, 0) / c0[c];
  }
  s.ljung_box_q = q;
  // The null's scale and degrees of freedom for the lags actually used (a short run may have
  // fewer than asked: the scale is kept, the dof shrink in proportion).
  const double scale = null.scale > 0.0 ? null.scale : 1.0;
  const double dof = null.dof * static_cast<double>(s.lags) / std::max(1, null.lags);
  s.ljung_box_z = ChiSquareNormalScore(q / scale, dof);
  s.lag1_autocorrelation = rho1_sum;
  // Integrated correlation with a Bartlett taper, so noise in the far lags does not dominate.
  double integrated = 1.0;
  for (Eigen::Index l = 1; l <= last; ++l)
    integrated +=
        2.0 * (1.0 - static_cast<double>(l) / static_cast<double>(last + 1)) * rho_sum[l - 1];
  s.integrated_correlation_samples = std::max(1.0, integrated);
  return s;
}

}  // namespace hrgbench::estimator
