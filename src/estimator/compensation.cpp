#include "hrgbench/estimator/compensation.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace hrgbench::estimator {

CompensationVector CompensationSet::AsVector() const {
  CompensationVector v;
  v << delta, xi, rate_bias_rad_s;
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
  where[kCompensationBias] = -1;  // free runs cannot see a bias
  for (int i = 0; i < 4; ++i) {
    const auto k = static_cast<std::size_t>(kCompensationXi + i);
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

RateErrorJacobian CompensationRateErrorJacobian(const CompensationSet& p,
                                                double omega_rad_s) noexcept {
  // Derivatives with respect to the compensation's own values, the truth held:
  // b = (δ2/δ̂2 − 1)·Ω − (b − b̂), c = −(δ4 − δ̂4)/(2δ2) − 2Ω(ξ1 − ξ̂1),
  // s = (δ3 − δ̂3)/(2δ2) − 2Ω(ξ4 − ξ̂4).
  RateErrorJacobian j = RateErrorJacobian::Zero();
  const double gain = p.delta[kScaleFactor];
  j(0, kScaleFactor) = -omega_rad_s / gain;
  j(0, kCompensationBias) = 1.0;
  j(1, kDampingAnisotropySin) = 1.0 / (2.0 * gain);
  j(1, kCompensationXi + kGainMismatch) = 2.0 * omega_rad_s;
  j(2, kDampingAnisotropyCos) = -1.0 / (2.0 * gain);
  j(2, kCompensationXi + kPickoffAngle) = 2.0 * omega_rad_s;
  return j;
}

Eigen::Matrix3d PredictedRateErrorCovariance(const CompensationSet& p,
                                             double omega_rad_s) noexcept {
  const RateErrorJacobian j = CompensationRateErrorJacobian(p, omega_rad_s);
  return j * p.covariance * j.transpose();
}

namespace {

// Weighted least squares of values y_j = a + b·Ω_j with std σ_j: (a, b) and their covariance.
bool InterceptAndSlope(std::span<const VerificationHold> holds, double VerificationHold::*value,
                       double VerificationHold::*std, Eigen::Vector2d* coef,
                       Eigen::Matrix2d* cov) noexcept {
  Eigen::Matrix2d info = Eigen::Matrix2d::Zero();
  Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
  for (const auto& hold : holds) {
    const double sigma = hold.*std;
    if (!(sigma > 0.0) || !std::isfinite(sigma) || !std::isfinite(hold.*value) ||
        !std::isfinite(hold.omega_rad_s)) {
      return false;
    }
    const Eigen::Vector2d row(1.0, hold.omega_rad_s);
    const double w = 1.0 / (sigma * sigma);
    info += w * row * row.transpose();
    rhs += w * row * (hold.*value);
  }
  const Eigen::FullPivLU<Eigen::Matrix2d> lu(info);
  if (!lu.isInvertible()) return false;  // fewer than two distinct rates
  *cov = lu.inverse();
  *coef = *cov * rhs;
  return true;
}

}  // namespace

bool RefineCompensation(const CompensationSet& p, std::span<const VerificationHold> holds,
                        CompensationRefinement* out) noexcept {
  const double two_gain = 2.0 * p.delta[kScaleFactor];
  if (out == nullptr || !(std::abs(two_gain) > 0.0) || !std::isfinite(two_gain)) return false;
  Eigen::Vector2d c, s, b;
  Eigen::Matrix2d c_cov, s_cov, b_cov;
  if (!InterceptAndSlope(holds, &VerificationHold::cos_rad_s, &VerificationHold::cos_std_rad_s, &c,
                         &c_cov) ||
      !InterceptAndSlope(holds, &VerificationHold::sin_rad_s, &VerificationHold::sin_std_rad_s, &s,
                         &s_cov) ||
      !InterceptAndSlope(holds, &VerificationHold::bias_rad_s, &VerificationHold::bias_std_rad_s,
                         &b, &b_cov)) {
    return false;
  }
  CompensationRefinement r;
  r.refined = p;
  // c0 = −Δδ4/(2δ2), s0 = Δδ3/(2δ2), b0 = the bias p leaves (Δ = operating mode − p).
  r.refined.delta[kDampingAnisotropySin] = p.delta[kDampingAnisotropySin] - two_gain * c[0];
  r.refined.delta[kDampingAnisotropyCos] = p.delta[kDampingAnisotropyCos] + two_gain * s[0];
  r.refined.rate_bias_rad_s = p.rate_bias_rad_s + b[0];
  // The refined values come from the table's data alone: their errors are the intercepts', and
  // independent of the free runs' (the rows and columns of the free runs' δ3, δ4 are replaced).
  for (const int i : {kDampingAnisotropyCos, kDampingAnisotropySin, kCompensationBias}) {
    r.refined.covariance.row(i).setZero();
    r.refined.covariance.col(i).setZero();
    r.refined.estimated[static_cast<std::size_t>(i)] = true;
  }
  r.refined.covariance(kDampingAnisotropySin, kDampingAnisotropySin) =
      two_gain * two_gain * c_cov(0, 0);
  r.refined.covariance(kDampingAnisotropyCos, kDampingAnisotropyCos) =
      two_gain * two_gain * s_cov(0, 0);
  r.refined.covariance(kCompensationBias, kCompensationBias) = b_cov(0, 0);
  // Slopes: c1 = −2Δξ1, s1 = −2Δξ4, b1 = δ2/δ̂2 − 1.
  r.slope_check << -0.5 * c[1], -0.5 * s[1], b[1];
  r.slope_check_std << 0.5 * std::sqrt(c_cov(1, 1)), 0.5 * std::sqrt(s_cov(1, 1)),
      std::sqrt(b_cov(1, 1));
  if (!r.refined.AsVector().allFinite() || !r.refined.covariance.allFinite()) return false;
  *out = r;
  return true;
}

}  // namespace hrgbench::estimator
