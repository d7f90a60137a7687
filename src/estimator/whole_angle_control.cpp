#include "hrgbench/estimator/whole_angle_control.hpp"

#include <cmath>
#include <numbers>

#include "hrgbench/estimator/model.hpp"

namespace hrgbench::estimator {

double CompensatedDrift(const CompensationSet& p, double angle_rad) noexcept {
  return p.delta[kDampingAnisotropySin] * std::cos(2.0 * angle_rad) -
         p.delta[kDampingAnisotropyCos] * std::sin(2.0 * angle_rad);
}

WholeAngleControl::WholeAngleControl(const CompensationSet& p, const WholeAngleLoopGains& gains,
                                     double sample_period_s) noexcept
    : p_(p), gains_(gains), h_(sample_period_s) {}

WholeAngleSample WholeAngleControl::Step(const Observation& y) noexcept {
  const State x = UndistortExact(p_.xi, y);
  const Forms z = QuadraticForms(x);
  WholeAngleSample out;
  out.energy = z[kS];
  out.quadrature = z[kK];

  // 2θ̂ unwrapped: the step from the last sample is taken as the shortest one, so the wave may turn
  // by up to π/2 (electrical) per sample.
  const double wrapped = std::atan2(z[kAs], z[kAc]);
  const double previous = two_theta_;
  two_theta_ =
      started_ ? previous + std::remainder(wrapped - previous, 2.0 * std::numbers::pi) : wrapped;
  out.angle_rad = 0.5 * two_theta_;
  if (started_) {
    const double mid_angle = 0.25 * (previous + two_theta_);
    // The energy loop's force, held over the period along the wave as it was at its start, drags
    // the turning wave back by g·h/2 of its turn (operating-mode.md "The sampled loop's drag").
    const double turn_rate = 0.5 * (two_theta_ - previous) / h_ /
                             (1.0 - held_effort_ * (0.5 * h_ + gains_.measurement_delay_s));
    out.rate_rad_s =
        -(turn_rate - CompensatedDrift(p_, mid_angle)) / (2.0 * p_.delta[kScaleFactor]) -
        p_.rate_bias_rad_s;
  }
  started_ = true;

  if (!(z[kS] > 0.0)) {  // no wave to hold: command nothing
    held_effort_ = 0.0;
    return out;
  }
  const double c2 = z[kAc], s2 = z[kAs];
  const double norm = std::hypot(c2, s2);
  const double cos2 = norm > 0.0 ? c2 / norm : 1.0;
  const double sin2 = norm > 0.0 ? s2 / norm : 0.0;

  const double amplitude_error = (gains_.energy_setpoint - z[kS]) / gains_.energy_setpoint;
  amplitude_integral_ += amplitude_error * h_;
  const double g = -p_.delta[kDamping] + gains_.amplitude_proportional_per_s * amplitude_error +
                   gains_.amplitude_integral_per_s2 * amplitude_integral_;

  const double quadrature_error = z[kK] / z[kS];
  quadrature_integral_ += quadrature_error * h_;
  const double feed_forward =
      p_.delta[kFrequencyAnisotropySin] * cos2 - p_.delta[kFrequencyAnisotropyCos] * sin2;
  const double q = -feed_forward - gains_.quadrature_proportional_per_s * quadrature_error -
                   gains_.quadrature_integral_per_s2 * quadrature_integral_;
  out.amplitude_effort_per_s = g;
  held_effort_ = g;
  out.quadrature_effort_rad_s = q;

  // u_a = −i·g·x̂ on (x1 + i·x2, x3 + i·x4): (g·x2, −g·x1, g·x4, −g·x3).
  // u_q = q·(−sin2θ̂·σz + cos2θ̂·σx)·x̂: channel 1 gets q·(−sin2θ̂·x̂_1 + cos2θ̂·x̂_2), channel 2
  // q·(sin2θ̂·x̂_2 + cos2θ̂·x̂_1), component by component (q and the angle are real).
  out.u[0] = g * x[1] + q * (-sin2 * x[0] + cos2 * x[2]);
  out.u[1] = -g * x[0] + q * (-sin2 * x[1] + cos2 * x[3]);
  out.u[2] = g * x[3] + q * (sin2 * x[2] + cos2 * x[0]);
  out.u[3] = -g * x[2] + q * (sin2 * x[3] + cos2 * x[1]);
  return out;
}

}  // namespace hrgbench::estimator
