#include "hrgbench/analysis/rate_error_harmonics.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace hrgbench::analysis {

RateErrorHarmonics FitRateErrorHarmonics(std::span<const double> angle_rad,
                                         std::span<const double> rate_error_rad_s,
                                         double sample_period_s, std::size_t window, int harmonics,
                                         RateErrorNoise noise) {
  RateErrorHarmonics out;
  if (angle_rad.size() != rate_error_rad_s.size()) {
    out.why = "angle and rate error have different lengths";
    return out;
  }
  if (window == 0 || harmonics < 1 || harmonics > 8 || !(sample_period_s > 0.0)) {
    out.why = "window must be at least 1 sample, harmonics 1 to 8, the sample period positive";
    return out;
  }
  const bool integrated = noise == RateErrorNoise::kWhiteAngle;
  const std::size_t windows = angle_rad.size() / window;
  // Bias and harmonics, and for the integrated error its free constant.
  const auto coefficients = static_cast<Eigen::Index>(1 + 2 * harmonics);
  const auto columns = coefficients + (integrated ? 1 : 0);
  if (windows < static_cast<std::size_t>(columns) + 2) {
    out.why = "too few windows for the harmonics asked";
    return out;
  }
  const auto rows = static_cast<Eigen::Index>(windows);
  Eigen::MatrixXd design = Eigen::MatrixXd::Zero(rows, columns);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(rows);
  // Running integrals (white angle) or per-sample values (white rate), averaged per window.
  Eigen::VectorXd running = Eigen::VectorXd::Zero(coefficients);
  double running_error = 0.0;
  double min_angle = 0.0, max_angle = 0.0;
  const double h = sample_period_s;
  Eigen::VectorXd regressor(coefficients);
  for (std::size_t w = 0; w < windows; ++w) {
    const auto r = static_cast<Eigen::Index>(w);
    double mean_angle = 0.0;
    for (std::size_t k = w * window; k < (w + 1) * window; ++k) {
      const double angle = angle_rad[k], error = rate_error_rad_s[k];
      if (!std::isfinite(angle) || !std::isfinite(error)) {
        out.why = "a sample is not finite";
        return out;
      }
      mean_angle += angle;
      regressor(0) = 1.0;
      for (int n = 1; n <= harmonics; ++n) {
        regressor(2 * n - 1) = std::cos(2.0 * n * angle);
        regressor(2 * n) = std::sin(2.0 * n * angle);
      }
      if (integrated) {
        running += h * regressor;
        running_error += h * error;
        design.row(r).head(coefficients) += running.transpose();
        rhs(r) += running_error;
      } else {
        design.row(r).head(coefficients) += regressor.transpose();
        rhs(r) += error;
      }
    }
    design.row(r).head(coefficients) /= static_cast<double>(window);
    rhs(r) /= static_cast<double>(window);
    if (integrated) design(r, coefficients) = 1.0;
    mean_angle /= static_cast<double>(window);
    min_angle = w == 0 ? mean_angle : std::min(min_angle, mean_angle);
    max_angle = w == 0 ? mean_angle : std::max(max_angle, mean_angle);
  }
  // Columns scaled to unit norm: the integrated regressors grow with time, the constant does not.
  const Eigen::VectorXd scale = design.colwise().norm().transpose().cwiseMax(1e-300);
  const Eigen::MatrixXd scaled = design * scale.cwiseInverse().asDiagonal();
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(scaled);
  qr.setThreshold(1e-10);
  if (qr.rank() < columns) {
    out.why = "the angles do not separate the bias from the harmonics (the wave did not turn)";
    return out;
  }
  const Eigen::VectorXd coef = qr.solve(rhs).cwiseQuotient(scale);
  const Eigen::VectorXd residual = rhs - design * coef;
  const double variance = residual.squaredNorm() / static_cast<double>(rows - columns);
  const Eigen::MatrixXd info = scaled.transpose() * scaled;
  const Eigen::MatrixXd scaled_cov =
      info.ldlt().solve(Eigen::MatrixXd::Identity(columns, columns)) * variance;
  const Eigen::VectorXd std = scaled_cov.diagonal().cwiseSqrt().cwiseQuotient(scale);
  out.ok = true;
  out.windows = windows;
  out.angle_span_rad = 2.0 * (max_angle - min_angle);
  out.bias_rad_s = coef(0);
  out.bias_std_rad_s = std(0);
  double sum_squares = 0.0;
  for (int n = 1; n <= harmonics; ++n) {
    const auto c = static_cast<Eigen::Index>(2 * n - 1), s = c + 1;
    out.cos_rad_s.push_back(coef(c));
    out.sin_rad_s.push_back(coef(s));
    out.cos_std_rad_s.push_back(std(c));
    out.sin_std_rad_s.push_back(std(s));
    sum_squares += coef(c) * coef(c) + coef(s) * coef(s);
  }
  out.angle_dependent_rms_rad_s = std::sqrt(sum_squares / 2.0);
  out.residual_rms = std::sqrt(residual.squaredNorm() / static_cast<double>(rows));
  return out;
}

}  // namespace hrgbench::analysis
