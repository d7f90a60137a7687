#include "sim/carrier_resonator.hpp"

#include <numbers>
#include <unsupported/Eigen/MatrixFunctions>

namespace hrgbench::drivers::sim {

CarrierResonator::CarrierResonator(const estimator::ResonatorParameters& resonator, double step_s)
    : resonator_(resonator),
      step_s_(step_s),
      velocity_scale_(2.0 * std::numbers::pi * resonator.frequency_hz) {
  Rebuild();
}

bool CarrierResonator::SetConditions(double omega_rad_s, double frequency_scale) noexcept {
  if (omega_rad_s == omega_rad_s_ && frequency_scale == frequency_scale_) return false;
  omega_rad_s_ = omega_rad_s;
  frequency_scale_ = frequency_scale;
  Rebuild();
  return true;
}

void CarrierResonator::Rebuild() noexcept {
  const estimator::OscillatorCoefficients o =
      estimator::OscillatorFromResonator(resonator_, frequency_scale_);
  Eigen::Matrix2d gyroscopic;  // coriolis·Ω·J, J = [[0, −1], [1, 0]]
  gyroscopic << 0.0, -o.coriolis * omega_rad_s_, o.coriolis * omega_rad_s_, 0.0;
  system_.setZero();
  system_.topRightCorner<2, 2>() = velocity_scale_ * Eigen::Matrix2d::Identity();
  system_.bottomLeftCorner<2, 2>() = -o.stiffness / velocity_scale_;
  system_.bottomRightCorner<2, 2>() = -o.damping - gyroscopic;
  if (!driven_) {
    transition_ = Transition(step_s_);
    return;
  }
  Eigen::Matrix<double, 6, 6> augmented = Eigen::Matrix<double, 6, 6>::Zero();
  augmented.topLeftCorner<4, 4>() = system_ * step_s_;
  augmented.block<2, 2>(2, 4) = Eigen::Matrix2d::Identity() * step_s_;
  const Eigen::Matrix<double, 6, 6> e = augmented.exp();
  transition_ = e.topLeftCorner<4, 4>();
  drive_ = e.topRightCorner<4, 2>();
}

void CarrierResonator::EnableDrive() noexcept {
  if (driven_) return;
  driven_ = true;
  Rebuild();
}

Eigen::Matrix4d CarrierResonator::Transition(double t_s) const noexcept {
  const Eigen::Matrix4d scaled = system_ * t_s;
  return scaled.exp();
}

double CarrierResonator::mean_frequency_rad_s() const noexcept {
  return 2.0 * std::numbers::pi * resonator_.frequency_hz * frequency_scale_;
}

void CarrierResonator::Release(const estimator::Orbit& orbit) noexcept {
  const estimator::State x0 = estimator::OrbitToState(orbit);
  const double w = mean_frequency_rad_s();
  // u = (x1 + i·x2, x3 + i·x4); q = Re u, q̇ = Re[iω·u] = −ω·Im u, stored as q̇/ω0.
  const double v = w / velocity_scale_;
  state_ << x0[0], x0[2], -v * x0[1], -v * x0[3];
}

}  // namespace hrgbench::drivers::sim
