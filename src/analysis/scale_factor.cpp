#include "hrgbench/analysis/scale_factor.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace hrgbench::analysis {

ScaleFactorFit FitScaleFactor(std::span<const RateHoldMean> holds) {
  ScaleFactorFit fit;
  // Weighted sums of the normal equations of e = b + ε·Ω.
  double sw = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, max_omega = 0.0;
  for (const RateHoldMean& h : holds) {
    if (!std::isfinite(h.omega_rad_s) || !std::isfinite(h.error_rad_s) ||
        !std::isfinite(h.std_rad_s) || !(h.std_rad_s > 0.0)) {
      fit.why = "a hold's rate, error or std is not finite and positive";
      return fit;
    }
    const double w = 1.0 / (h.std_rad_s * h.std_rad_s);
    sw += w;
    sx += w * h.omega_rad_s;
    sy += w * h.error_rad_s;
    sxx += w * h.omega_rad_s * h.omega_rad_s;
    sxy += w * h.omega_rad_s * h.error_rad_s;
    max_omega = std::max(max_omega, std::abs(h.omega_rad_s));
  }
  const double det = sw * sxx - sx * sx;
  // Two distinct rates: the spread of Ω about its weighted mean is not zero (relative to Ω²).
  if (holds.size() < 2 || !(det > 1e-12 * sw * sxx)) {
    fit.why = "two distinct rates are needed";
    return fit;
  }
  fit.scale_factor_error = (sw * sxy - sx * sy) / det;
  fit.bias_rad_s = (sxx * sy - sx * sxy) / det;
  double max_residual = 0.0;
  for (const RateHoldMean& h : holds) {
    const double r = h.error_rad_s - fit.bias_rad_s - fit.scale_factor_error * h.omega_rad_s;
    fit.chi2 += r * r / (h.std_rad_s * h.std_rad_s);
    max_residual = std::max(max_residual, std::abs(r));
  }
  fit.dof = static_cast<int>(holds.size()) - 2;
  const double birge = fit.dof > 0 ? std::max(1.0, std::sqrt(fit.chi2 / fit.dof)) : 1.0;
  fit.scale_factor_error_std = birge * std::sqrt(sw / det);
  fit.bias_std_rad_s = birge * std::sqrt(sxx / det);
  fit.nonlinearity_known = fit.dof > 0;
  fit.nonlinearity = fit.nonlinearity_known ? max_residual / max_omega : 0.0;
  // The asymmetry: e = b + ε·Ω + α·|Ω|, weighted least squares by its normal equations.
  bool positive = false, negative = false;
  double min_abs = INFINITY, max_abs = 0.0;
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d right = Eigen::Vector3d::Zero();
  for (const RateHoldMean& h : holds) {
    const Eigen::Vector3d a(1.0, h.omega_rad_s, std::abs(h.omega_rad_s));
    const double w = 1.0 / (h.std_rad_s * h.std_rad_s);
    normal += w * a * a.transpose();
    right += w * h.error_rad_s * a;
    positive = positive || h.omega_rad_s > 0.0;
    negative = negative || h.omega_rad_s < 0.0;
    min_abs = std::min(min_abs, std::abs(h.omega_rad_s));
    max_abs = std::max(max_abs, std::abs(h.omega_rad_s));
  }
  if (positive && negative && holds.size() >= 3 && max_abs - min_abs > 1e-3 * max_abs) {
    const Eigen::FullPivLU<Eigen::Matrix3d> lu(normal);
    if (lu.isInvertible() && lu.rcond() > 1e-12) {
      const Eigen::Vector3d x = lu.solve(right);
      const Eigen::Matrix3d covariance = lu.inverse();
      double chi2 = 0.0;
      for (const RateHoldMean& h : holds) {
        const double r =
            h.error_rad_s - x[0] - x[1] * h.omega_rad_s - x[2] * std::abs(h.omega_rad_s);
        chi2 += r * r / (h.std_rad_s * h.std_rad_s);
      }
      const int dof = static_cast<int>(holds.size()) - 3;
      const double scale = dof > 0 ? std::max(1.0, std::sqrt(chi2 / dof)) : 1.0;
      fit.asymmetry_known = true;
      fit.asymmetry = 2.0 * x[2];
      fit.asymmetry_std = 2.0 * scale * std::sqrt(covariance(2, 2));
    }
  }
  fit.ok = true;
  return fit;
}

}  // namespace hrgbench::analysis
