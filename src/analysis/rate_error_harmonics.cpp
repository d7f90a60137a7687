#include "hrgbench/analysis/rate_error_harmonics.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace hrgbench::analysis {

RateErrorHarmonics FitRateErrorHarmonics(std::span<const double> angle_rad,
                                         std::span<const double> rate_error_rad_s,
                                         std::size_t window, int harmonics) {
  RateErrorHarmonics out;
  if (angle_rad.size() != rate_error_rad_s.size()) {
    out.why = "angle and rate error have different lengths";
    return out;
  }
  if (window == 0 || harmonics < 1 || harmonics > 8) {
    out.why = "window must be at least 1 sample and harmonics 1 to 8";
    return out;
  }
  const std::size_t windows = angle_rad.size() / window;
  const auto columns = static_cast<Eigen::Index>(1 + 2 * harmonics);
  if (windows < static_cast<std::size_t>(columns) + 2) {
    out.why = "too few windows for the harmonics asked";
    return out;
  }
  const auto rows = static_cast<Eigen::Index>(windows);
  Eigen::MatrixXd design(rows, columns);
  Eigen::VectorXd rhs(rows);
  double min_angle = 0.0, max_angle = 0.0;
  for (std::size_t w = 0; w < windows; ++w) {
    double angle = 0.0, error = 0.0;
    for (std::size_t k = w * window; k < (w + 1) * window; ++k) {
      angle += angle_rad[k];
      error += rate_error_rad_s[k];
    }
    angle /= static_cast<double>(window);
    error /= static_cast<double>(window);
    if (!std::isfinite(angle) || !std::isfinite(error)) {
      out.why = "a sample is not finite";
      return out;
    }
    const auto r = static_cast<Eigen::Index>(w);
    design(r, 0) = 1.0;
    for (int n = 1; n <= harmonics; ++n) {
      design(r, 2 * n - 1) = std::cos(2.0 * n * angle);
      design(r, 2 * n) = std::sin(2.0 * n * angle);
    }
    rhs(r) = error;
    min_angle = w == 0 ? angle : std::min(min_angle, angle);
    max_angle = w == 0 ? angle : std::max(max_angle, angle);
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(design);
  if (qr.rank() < columns) {
    out.why = "the angles do not separate the bias from the harmonics (the wave did not turn)";
    return out;
  }
  const Eigen::VectorXd coef = qr.solve(rhs);
  const Eigen::VectorXd residual = rhs - design * coef;
  const double dof = static_cast<double>(rows - columns);
  const double variance = residual.squaredNorm() / dof;
  const Eigen::MatrixXd info = design.transpose() * design;
  const Eigen::MatrixXd cov =
      info.ldlt().solve(Eigen::MatrixXd::Identity(columns, columns)) * variance;
  out.ok = true;
  out.windows = windows;
  out.angle_span_rad = 2.0 * (max_angle - min_angle);
  out.bias_rad_s = coef(0);
  out.bias_std_rad_s = std::sqrt(cov(0, 0));
  double sum_squares = 0.0;
  for (int n = 1; n <= harmonics; ++n) {
    const auto c = static_cast<Eigen::Index>(2 * n - 1), s = c + 1;
    out.cos_rad_s.push_back(coef(c));
    out.sin_rad_s.push_back(coef(s));
    out.cos_std_rad_s.push_back(std::sqrt(cov(c, c)));
    out.sin_std_rad_s.push_back(std::sqrt(cov(s, s)));
    sum_squares += coef(c) * coef(c) + coef(s) * coef(s);
  }
  out.angle_dependent_rms_rad_s = std::sqrt(sum_squares / 2.0);
  out.residual_rms_rad_s = std::sqrt(residual.squaredNorm() / static_cast<double>(rows));
  return out;
}

}  // namespace hrgbench::analysis
