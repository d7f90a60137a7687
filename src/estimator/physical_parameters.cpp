#include "hrgbench/estimator/physical_parameters.hpp"

#include <cmath>
#include <numbers>

namespace hrgbench::estimator {
namespace {

using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;

bool Fail(std::string* why, const char* message) {
  if (why != nullptr) *why = message;
  return false;
}

// Half the angle of a vector in the doubled-angle plane, in (−π/2, π/2]; 0 for the zero vector
// (std::atan2(0, 0) is 0, and atan2(±0, −x) = ±π gives −π/2 for −0: fold it onto π/2).
double HalfAngle(double y, double x) noexcept {
  if (x == 0.0 && y == 0.0) return 0.0;
  double angle = 0.5 * std::atan2(y, x);
  if (angle <= -0.5 * kPi) angle += kPi;
  return angle;
}

// P(β) = [[cos2β, sin2β], [sin2β, −cos2β]].
Eigen::Matrix2d Traceless(double beta) noexcept {
  const double c = std::cos(2.0 * beta), s = std::sin(2.0 * beta);
  Eigen::Matrix2d p;
  p << c, s, s, -c;
  return p;
}

}  // namespace

double ResonatorParameters::QualityFactor() const noexcept {
  return kPi * frequency_hz * decay_time_s;
}

bool ResonatorParameters::IsValid(std::string* why) const {
  if (!(std::isfinite(frequency_hz) && frequency_hz > 0.0)) {
    return Fail(why, "frequency_hz must be finite and > 0");
  }
  if (!(std::isfinite(decay_time_s) && decay_time_s > 0.0)) {
    return Fail(why, "decay_time_s must be finite and > 0");
  }
  if (!(std::isfinite(damping_anisotropy_per_s) && damping_anisotropy_per_s >= 0.0)) {
    return Fail(why, "damping_anisotropy_per_s must be finite and >= 0");
  }
  if (!(std::isfinite(frequency_split_hz) && frequency_split_hz >= 0.0 &&
        frequency_split_hz < frequency_hz)) {
    return Fail(why, "frequency_split_hz must be finite and in [0, frequency_hz)");
  }
  if (!std::isfinite(damping_axis_rad) || !std::isfinite(frequency_axis_rad) ||
      !std::isfinite(angular_gain)) {
    return Fail(why, "damping_axis_rad, frequency_axis_rad and angular_gain must be finite");
  }
  return true;
}

bool PickoffParameters::IsValid(std::string* why) const {
  if (!(std::isfinite(gain_ratio) && gain_ratio > 0.0)) {
    return Fail(why, "gain_ratio must be finite and > 0");
  }
  if (!(std::isfinite(phase_mismatch_rad) && std::abs(phase_mismatch_rad) < kPi)) {
    return Fail(why, "phase_mismatch_rad must be finite and within (-pi, pi)");
  }
  if (!std::isfinite(cross_talk)) return Fail(why, "cross_talk must be finite");
  if (!(std::isfinite(electrode_angle_error_rad) && std::abs(electrode_angle_error_rad) < kPi)) {
    return Fail(why, "electrode_angle_error_rad must be finite and within (-pi, pi)");
  }
  return true;
}

Delta DeltaFromResonator(const ResonatorParameters& r) noexcept {
  const double half_damping = 0.5 * r.damping_anisotropy_per_s;
  const double half_split = kPi * r.frequency_split_hz;  // Δω/2 = π·Δf, rad/s
  Delta delta;
  delta[kDamping] = -1.0 / r.decay_time_s;
  delta[kScaleFactor] = r.angular_gain;
  delta[kDampingAnisotropyCos] = -half_damping * std::cos(2.0 * r.damping_axis_rad);
  delta[kDampingAnisotropySin] = -half_damping * std::sin(2.0 * r.damping_axis_rad);
  delta[kFrequencyAnisotropyCos] = half_split * std::cos(2.0 * r.frequency_axis_rad);
  delta[kFrequencyAnisotropySin] = half_split * std::sin(2.0 * r.frequency_axis_rad);
  return delta;
}

ResonatorParameters ResonatorFromDelta(const Delta& delta, double frequency_hz) noexcept {
  ResonatorParameters r;
  r.frequency_hz = frequency_hz;
  r.decay_time_s = -1.0 / delta[kDamping];
  r.angular_gain = delta[kScaleFactor];
  const double d3 = delta[kDampingAnisotropyCos], d4 = delta[kDampingAnisotropySin];
  r.damping_anisotropy_per_s = 2.0 * std::hypot(d3, d4);
  r.damping_axis_rad = HalfAngle(-d4, -d3);
  const double d5 = delta[kFrequencyAnisotropyCos], d6 = delta[kFrequencyAnisotropySin];
  r.frequency_split_hz = std::hypot(d5, d6) / kPi;
  r.frequency_axis_rad = HalfAngle(d6, d5);
  return r;
}

Eigen::Matrix2cd ComplexDistortion(const Xi& xi) noexcept {
  const Complex p(xi[kGainMismatch], -xi[kPhaseMismatch]);
  const Complex q(xi[kPickoffAngle], -xi[kCrossTalk]);
  Eigen::Matrix2cd h;
  h << 1.0 + p, q, q, 1.0 - p;
  return h;
}

OscillatorCoefficients OscillatorFromResonator(const ResonatorParameters& r,
                                               double frequency_scale) noexcept {
  OscillatorCoefficients o;
  o.damping = (2.0 / r.decay_time_s) * Eigen::Matrix2d::Identity() +
              r.damping_anisotropy_per_s * Traceless(r.damping_axis_rad);
  const double w1 = 2.0 * kPi * (r.frequency_hz + 0.5 * r.frequency_split_hz) * frequency_scale;
  const double w2 = 2.0 * kPi * (r.frequency_hz - 0.5 * r.frequency_split_hz) * frequency_scale;
  // R·diag(w1², w2²)·Rᵀ = mean·I + half_difference·P(θ_ω).
  o.stiffness = 0.5 * (w1 * w1 + w2 * w2) * Eigen::Matrix2d::Identity() +
                0.5 * (w1 * w1 - w2 * w2) * Traceless(r.frequency_axis_rad);
  o.coriolis = 4.0 * r.angular_gain;
  return o;
}

}  // namespace hrgbench::estimator
