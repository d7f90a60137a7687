#include "hrgbench/estimator/compensation.hpp"

#include <cmath>

namespace hrgbench::estimator {

CompensationVector CompensationSet::AsVector() const {
  CompensationVector v;
  v << delta, xi;
  return v;
}

CompensationSet IdentityCompensation(double nominal_angular_gain, double nominal_damping_per_s) {
  CompensationSet p;
  p.delta[kDamping] = nominal_damping_per_s;
  p.delta[kScaleFactor] = nominal_angular_gain;
  return p;
}

bool CompensationFromEstimate(const EstimateSummary& estimate, CompensationSet* out) noexcept {
  if (out == nullptr || !estimate.IsUsable()) return false;
  const double gain = estimate.delta[kScaleFactor];
  if (!std::isfinite(gain) || gain == 0.0) return false;
  CompensationSet p;
  // The summary's covariance holds the estimated components only, δ first then ξ, in index order.
  std::array<int, kCompensationSize> where{};
  int n = 0;
  for (int i = 0; i < 6; ++i) {
    p.delta[i] = estimate.delta[i];
    p.estimated[static_cast<std::size_t>(i)] =
        estimate.delta_estimated[static_cast<std::size_t>(i)];
    where[static_cast<std::size_t>(i)] = p.estimated[static_cast<std::size_t>(i)] ? n++ : -1;
  }
  for (int i = 0; i < 4; ++i) {
    const auto k = static_cast<std::size_t>(6 + i);
    p.xi[i] = estimate.xi[i];
    p.estimated[k] = estimate.xi_estimated[static_cast<std::size_t>(i)];
    where[k] = p.estimated[k] ? n++ : -1;
  }
  if (!p.AsVector().allFinite()) return false;
  if (estimate.covariance.rows() != n || estimate.covariance.cols() != n) return false;
  for (std::size_t i = 0; i < where.size(); ++i) {
    if (where[i] < 0) continue;
    for (std::size_t j = 0; j < where.size(); ++j) {
      if (where[j] < 0) continue;
      p.covariance(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
          estimate.covariance(where[i], where[j]);
    }
  }
  if (!p.covariance.allFinite()) return false;
  *out = p;
  return true;
}

Eigen::Matrix<double, 2, kCompensationSize> AngleDependentRateErrorJacobian(
    const CompensationSet& p, double omega_rad_s) noexcept {
  // c = −(δ4 − δ̂4)/(2δ2) − 2Ω(ξ1 − ξ̂1),  s = (δ3 − δ̂3)/(2δ2) − 2Ω(ξ4 − ξ̂4): derivatives with
  // respect to the compensation's own values (the truth held).
  Eigen::Matrix<double, 2, kCompensationSize> j =
      Eigen::Matrix<double, 2, kCompensationSize>::Zero();
  const double two_gain = 2.0 * p.delta[kScaleFactor];
  j(0, kDampingAnisotropySin) = 1.0 / two_gain;
  j(0, 6 + kGainMismatch) = 2.0 * omega_rad_s;
  j(1, kDampingAnisotropyCos) = -1.0 / two_gain;
  j(1, 6 + kPickoffAngle) = 2.0 * omega_rad_s;
  return j;
}

Eigen::Matrix2d PredictedAngleDependentRateErrorCovariance(const CompensationSet& p,
                                                           double omega_rad_s) noexcept {
  const auto j = AngleDependentRateErrorJacobian(p, omega_rad_s);
  return j * p.covariance * j.transpose();
}

}  // namespace hrgbench::estimator
