#pragma once
// ControlledResonator: the slow model with the control in it, the paper's full model
//
//   dx/dt = A(Ω, δ)·x + B0·F·u,   y = (I + C(ξ))·x + D·u + σ·n,
//
// for the operating mode (docs/estimator/operating-mode.md). u = (u1 + i·u2, u3 + i·u4) is the
// electronics' command, held between samples (zero-order hold); B0 multiplies it by i (the paper's
// B0: the force in phase with the velocity); F = I + B(ε) is the forcers' complex 2×2 gain (their
// gain and phase mismatch, cross-coupling and electrode angle), D = D(η) the command's feed-through
// into the pick-off, both on the complex slow variables like C(ξ).
//
// The state is advanced by the exact discretisation of that linear system over each period,
// x ← Φ·x + Γ·u with Φ = exp(A·h), Γ = ∫₀ʰ exp(A·s) ds·B0·F, from the exponential of the augmented
// matrix [[A, B0·F], [0, 0]]·h (scaling and squaring of its Taylor series), computed here and not
// taken from the estimator, whose propagator the tests check against it. Ω may change between
// periods (the table's rate; Φ and Γ are recomputed).

#include <Eigen/Core>
#include <complex>
#include <cstdint>

#include "hrgbench/estimator/parameters.hpp"
#include "hrgbench/estimator/simulation.hpp"

namespace hrgbench::drivers::sim {

struct ControlledResonatorTruth {
  estimator::Delta delta = estimator::Delta::Zero();
  estimator::Xi xi = estimator::Xi::Zero();
  Eigen::Matrix2cd forcer_gain = Eigen::Matrix2cd::Identity();  // F = I + B(ε)
  Eigen::Matrix2cd feed_through = Eigen::Matrix2cd::Zero();     // D(η)
  double sigma = 0.0;  // pick-off noise per channel, y's units
  std::uint64_t seed = 1;
};

// A complex 2×2 acting on (x1 + i·x2, x3 + i·x4) as the real 4×4 acting on x.
Eigen::Matrix4d RealForm(const Eigen::Matrix2cd& m) noexcept;

class ControlledResonator {
 public:
  ControlledResonator(const ControlledResonatorTruth& truth, double omega_rad_s,
                      double sample_period_s, const estimator::State& x0);

  // The sample at the current time, with `u` the command being applied now (feed-through).
  estimator::Observation Observe(const Eigen::Vector4d& u);
  // Advances one period with `u` held; then the caller observes the next sample.
  void Advance(const Eigen::Vector4d& u) noexcept;
  void SetOmega(double omega_rad_s) noexcept;

  const estimator::State& state() const noexcept { return x_; }
  double time_s() const noexcept { return t_s_; }

 private:
  void Discretise() noexcept;

  ControlledResonatorTruth truth_;
  double omega_rad_s_;
  double h_;
  estimator::State x_;
  double t_s_ = 0.0;
  Eigen::Matrix4d distortion_;    // I + C(ξ)
  Eigen::Matrix4d force_input_;   // B0·F, real form
  Eigen::Matrix4d feed_through_;  // D, real form
  Eigen::Matrix4d phi_;
  Eigen::Matrix4d gamma_;
  estimator::NormalGenerator noise_;
};

}  // namespace hrgbench::drivers::sim
