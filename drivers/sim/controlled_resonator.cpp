#include "sim/controlled_resonator.hpp"

#include <cmath>

#include "hrgbench/estimator/model.hpp"

namespace hrgbench::drivers::sim {
namespace {

using Matrix8 = Eigen::Matrix<double, 8, 8>;

// exp(M) by scaling and squaring: M/2^s has a norm ≤ 1/2, where the Taylor series to degree 16
// is exact to well below double rounding (0.5^17/17! ≈ 5e-21); then s squarings.
Matrix8 Exponential(const Matrix8& m) noexcept {
  const double norm = m.cwiseAbs().rowwise().sum().maxCoeff();
  int squarings = 0;
  if (norm > 0.5) squarings = static_cast<int>(std::ceil(std::log2(norm / 0.5)));
  const Matrix8 scaled = m / std::ldexp(1.0, squarings);
  Matrix8 result = Matrix8::Identity();
  Matrix8 term = Matrix8::Identity();
  for (int k = 1; k <= 16; ++k) {
    term = term * scaled / static_cast<double>(k);
    result += term;
  }
  for (int i = 0; i < squarings; ++i) result = result * result;
  return result;
}

}  // namespace

Eigen::Matrix4d RealForm(const Eigen::Matrix2cd& m) noexcept {
  Eigen::Matrix4d r;
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      const double re = m(i, j).real(), im = m(i, j).imag();
      r.block<2, 2>(2 * i, 2 * j) << re, -im, im, re;
    }
  }
  return r;
}

ControlledResonator::ControlledResonator(const ControlledResonatorTruth& truth, double omega_rad_s,
                                         double sample_period_s, const estimator::State& x0)
    : truth_(truth),
      omega_rad_s_(omega_rad_s),
      h_(sample_period_s),
      x_(x0),
      distortion_(Eigen::Matrix4d::Identity() + estimator::DistortionMatrix(truth.xi)),
      force_input_(RealForm(std::complex<double>(0.0, 1.0) * truth.forcer_gain)),
      feed_through_(RealForm(truth.feed_through)),
      noise_(truth.seed) {
  Discretise();
}

void ControlledResonator::Discretise() noexcept {
  Matrix8 augmented = Matrix8::Zero();
  augmented.topLeftCorner<4, 4>() = estimator::SystemMatrix(omega_rad_s_, truth_.delta) * h_;
  augmented.topRightCorner<4, 4>() = force_input_ * h_;
  const Matrix8 e = Exponential(augmented);
  phi_ = e.topLeftCorner<4, 4>();
  gamma_ = e.topRightCorner<4, 4>();
}

void ControlledResonator::SetOmega(double omega_rad_s) noexcept {
  if (omega_rad_s == omega_rad_s_) return;
  omega_rad_s_ = omega_rad_s;
  Discretise();
}

estimator::Observation ControlledResonator::Observe(const Eigen::Vector4d& u) {
  estimator::Observation y = distortion_ * x_ + feed_through_ * u;
  if (truth_.sigma > 0.0) {
    for (int i = 0; i < 4; ++i) y[i] += truth_.sigma * noise_.Next();
  }
  return y;
}

void ControlledResonator::Advance(const Eigen::Vector4d& u) noexcept {
  x_ = phi_ * x_ + gamma_ * u;
  t_s_ += h_;
}

}  // namespace hrgbench::drivers::sim
