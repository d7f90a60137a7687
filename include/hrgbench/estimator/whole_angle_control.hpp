#pragma once
// The gyro as a gyro: the paper's control u = V(y, p) of a rate-integrating (whole-angle) HRG in
// the slow variables, and its angle and rate readout (docs/estimator/operating-mode.md).
//
// Every sample period h the electronics read y, undo the pick-off with p's ξ̂
// (x̂ = (I + C(ξ̂))⁻¹·y), form ẑ = (Âc, Âs, K̂, Ŝ) and the wave angle 2θ̂ = atan2(Âs, Âc), and command
// the force u (held until the next sample) that the forcers apply as dx/dt = A·x + B0·F·u, B0 the
// multiplication by i of u = (u1 + i·u2, u3 + i·u4) (the paper's B0: a force in phase with the
// velocity), F the forcers' gain (I + B(ε); I for ideal forcers):
//
//   amplitude loop   u_a = −i·g·x̂,  g = −δ̂1 + PI[(S* − Ŝ)/S*]: the velocity-phased force along
//                    the wave itself, making up its decay and holding its energy S at S*; with
//                    ideal forcers it changes neither θ nor the quadrature;
//   quadrature loop  u_q = q·(−sin2θ̂·σz + cos2θ̂·σx)·x̂,  q = −(δ̂6·cos2θ̂ − δ̂5·sin2θ̂) − PI[K̂/Ŝ]:
//                    a stiffness split at 45° (electrical) to the wave, the only one that moves K
//                    (dK/dt = 2q·(a² − b²)) and, with K at zero, not θ; p's split is fed forward so
//                    the loop only trims what p has wrong.
//
// The wave angle is free (whole-angle mode): under a rate Ω it turns at θ' = −2δ2·Ω + d(θ), the
// drift d(θ) = δ4·cos2θ − δ3·sin2θ of the damping anisotropy (with K at zero). The rate output of
// the period ending at sample k is Ω̂ = −((θ̂_k − θ̂_{k−1})/h − d̂(θ̂_mid))/(2·δ̂2) − b̂, θ̂ unwrapped,
// with p's δ̂2, δ̂3, δ̂4 and bias b̂; θ̂ is the electrical angle (the pattern on the shell turns at half
// of it, n = 2). The turn is first divided by (1 − g·h/2): the energy loop's force, held over a
// period along the wave as it was at the period's start, drags the turning wave back by that much
// (0.5 ppm of the rate at g = 1e-3 1/s, h = 1 ms; operating-mode.md "The sampled loop's drag"),
// and by 1 − g·τm more when the samples show the wave τm late (a demodulator's low-pass: the force
// is along the wave as it was τm ago; 2.1 ppm for a 4th-order 200 Hz Butterworth).
//
// Real-time: no allocation, no exception; Step is O(1).

#include "hrgbench/estimator/compensation.hpp"
#include "hrgbench/estimator/parameters.hpp"

namespace hrgbench::estimator {

struct WholeAngleLoopGains {
  double energy_setpoint = 1.0;  // S*, in y's units squared (the wave's a² + b²)
  // Each loop's error e obeys e' = −2·(kp·e + ki·∫e) near its set point: kp = 20 1/s and
  // ki = 200 1/s² put both poles at −20 rad/s (critically damped), far below a 1 kHz sample rate
  // (2·kp·h = 0.04) and far above the rate at which a turning wave moves the split's feed-forward
  // error (2·θ' ≈ 1.2 rad/s at 1 rad/s).
  double amplitude_proportional_per_s = 20.0;
  double amplitude_integral_per_s2 = 200.0;
  double quadrature_proportional_per_s = 20.0;
  double quadrature_integral_per_s2 = 200.0;
  // τm, s: how late the samples show the wave (the electronics' demodulator group delay; 0 in the
  // slow model, whose samples are the wave now). The readout removes the drag it causes (above).
  double measurement_delay_s = 0.0;
};

// What one step read and commanded.
struct WholeAngleSample {
  Eigen::Vector4d u = Eigen::Vector4d::Zero();  // the command, held over the next period
  double angle_rad = 0.0;    // θ̂, electrical, unwrapped (continuous over turns)
  double rate_rad_s = kNaN;  // Ω̂ over the period that ended at this sample (NaN on the first)
  double energy = 0.0;       // Ŝ
  double quadrature = 0.0;   // K̂
  double amplitude_effort_per_s = 0.0;   // g
  double quadrature_effort_rad_s = 0.0;  // q
};

class WholeAngleControl {
 public:
  WholeAngleControl(const CompensationSet& p, const WholeAngleLoopGains& gains,
                    double sample_period_s) noexcept;

  // One sample of the demodulated channels in, the command to hold until the next one out.
  WholeAngleSample Step(const Observation& y) noexcept;

  const CompensationSet& compensation() const noexcept { return p_; }

 private:
  CompensationSet p_;
  WholeAngleLoopGains gains_;
  double h_;
  bool started_ = false;
  double two_theta_ = 0.0;  // unwrapped 2θ̂ of the last sample
  double amplitude_integral_ = 0.0;
  double quadrature_integral_ = 0.0;
  double held_effort_ = 0.0;  // g of the command being held
};

// d̂(θ) = δ̂4·cos2θ − δ̂3·sin2θ: the drift p removes from the rate, rad/s.
double CompensatedDrift(const CompensationSet& p, double angle_rad) noexcept;

}  // namespace hrgbench::estimator
