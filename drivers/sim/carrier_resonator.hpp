#pragma once
// CarrierResonator: the n = 2 working mode as the 2-DOF linear oscillator at its carrier,
//
//     q̈ + D·q̇ + K(T)·q + 4kΩ·J·q̇ = 0      (estimator/physical_parameters.hpp: D, K, J, k),
//
// state X = (q1, q2, q̇1/ω0, q̇2/ω0) with ω0 = 2π·f0 fixed (velocity in displacement units: F·dt
// is then balanced, |F·dt| ≈ ω0·dt, so exp(F·dt) is accurate to rounding in every entry; with the
// raw velocity K·dt ≈ 1e4 against dt ≈ 1e-5 and the exponential loses ~4 digits),
// dX/dt = F·X, F = [[0, ω0·I], [−K/ω0, −D − 4kΩJ]]. The mode frequencies
// scale with temperature, f(T) = f0·(1 + α·(T − T0)), through `frequency_scale` = f(T)/f0.
//
// Exact in time: every step is X ← Φ·X with Φ = exp(F·dt) (Padé with scaling and squaring, to
// rounding), recomputed only when Ω or the frequency scale changes (the caller holds them piecewise
// constant, e.g. per output sample). No small-step integrator, so 1e7 steps of 10 µs lose nothing
// but rounding (~1e-16 per step, relative).
//
// Release: the commanded wave state (a, b, θ, φ) becomes the oscillator's state through the
// demodulation convention of physical_parameters.hpp: u0 = OrbitToState(orbit) as complex pairs,
// q = Re[u0], q̇ = Re[iω·u0] with ω the mean mode frequency at release (osculating variables: the
// state a reference locked to the wave at ω, phase 0, demodulates to x0 exactly).
//
// Driven (the operating mode, carrier_simulation.hpp): a force per unit mass f = (f1, f2) on q,
// held over a step, enters as w = f/ω0 on the velocity rows, X ← Φ·X + Γ·w with
// Γ = ∫₀^dt exp(F·s) ds·[0; I], both from one exponential of the augmented 6×6 [[F, [0; I]], 0]·dt
// (so the input column is dt, balanced like F·dt). Only after EnableDrive(): free runs keep the
// 4×4.
//
// Threads: one thread. Real-time: Step() and state() are allocation-free and noexcept;
// SetConditions() computes a 4×4 (driven: 6×6) matrix exponential (a few µs) when something
// changed.

#include "hrgbench/estimator/model.hpp"
#include "hrgbench/estimator/physical_parameters.hpp"

namespace hrgbench::drivers::sim {

using CarrierState = Eigen::Vector4d;  // (q1, q2, q̇1/ω0, q̇2/ω0), all in the unit of a

class CarrierResonator {
 public:
  // `step_s` > 0 is the time step of Step(). The resonator must be valid (IsValid).
  CarrierResonator(const estimator::ResonatorParameters& resonator, double step_s);

  // Ω [rad/s] and f(T)/f0 from now on. Recomputes F and Φ only when either differs from before;
  // true when it did.
  bool SetConditions(double omega_rad_s, double frequency_scale) noexcept;
  // The state of the wave (a, b, θ, φ) at release, under the current conditions.
  void Release(const estimator::Orbit& orbit) noexcept;

  void Step() noexcept { state_ = transition_ * state_; }
  // From now on Rebuild also computes Γ (above); recomputes it for the current conditions.
  void EnableDrive() noexcept;
  // One step with the force w = f/ω0 (per unit mass, over ω0) held over it. EnableDrive first.
  void StepDriven(const Eigen::Vector2d& w) noexcept { state_ = transition_ * state_ + drive_ * w; }
  // One step with a given transition (CarrierSimulation interpolates it under a temperature ramp).
  void StepWith(const Eigen::Matrix4d& transition) noexcept { state_ = transition * state_; }
  const Eigen::Matrix4d& transition() const noexcept { return transition_; }  // exp(F·step_s)
  const CarrierState& state() const noexcept { return state_; }
  void set_state(const CarrierState& state) noexcept { state_ = state; }

  // exp(F·t) under the current conditions, any t (negative: back in time, for a pick-off delay).
  Eigen::Matrix4d Transition(double t_s) const noexcept;
  const Eigen::Matrix4d& system_matrix() const noexcept { return system_; }  // F
  // Mean of the two mode frequencies now, rad/s: 2π·f0·frequency_scale.
  double mean_frequency_rad_s() const noexcept;
  double velocity_scale_rad_s() const noexcept { return velocity_scale_; }  // ω0 = 2π·f0
  const estimator::ResonatorParameters& resonator() const noexcept { return resonator_; }
  double step_s() const noexcept { return step_s_; }

 private:
  void Rebuild() noexcept;

  estimator::ResonatorParameters resonator_;
  double step_s_;
  double velocity_scale_;
  double omega_rad_s_ = 0.0;
  double frequency_scale_ = 1.0;
  Eigen::Matrix4d system_;
  Eigen::Matrix4d transition_;
  bool driven_ = false;
  Eigen::Matrix<double, 4, 2> drive_ = Eigen::Matrix<double, 4, 2>::Zero();  // Γ
  CarrierState state_ = CarrierState::Zero();
};

}  // namespace hrgbench::drivers::sim
