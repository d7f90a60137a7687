#pragma once
// Physical parameters of the n = 2 working mode and of the pick-off path, and their exact map to
// and from the model's (δ, ξ) of docs/estimator/model.md. Pure functions, Eigen and the standard
// library only, no I/O, noexcept, no validation inside the maps (IsValid says what is meaningful).
//
// ## The oscillator
// The working mode as a 2-DOF linear oscillator in the coordinates q = (q1, q2) that the two
// pick-off channels see (channel 1's electrode at 0, channel 2's at 45° on the shell):
//
//     q̈ + D·q̇ + K·q + 4kΩ·J·q̇ = 0,        J = | 0 −1 |
//                                                | 1  0 |
//
//   D = (2/τ)·I + Δ(1/τ)·P(θ_τ),   K = R(θ_ω)·diag(ω1², ω2²)·R(θ_ω)ᵀ,   ω1,2 = 2π(f0 ± Δf/2),
//   P(β) = | cos2β  sin2β |   (traceless; eigenvector (cosβ, sinβ) with eigenvalue +1).
//          | sin2β −cos2β |
//
// ALL ANGLES here (θ_τ, θ_ω, the electrode angle error, and the wave angle θ of Orbit) are in the
// frame of q, the "electrical" frame of model.md where channel 2's electrode sits at 90°; on the
// shell (n = 2) every angle is half of this. A wave at θ = θ_ω vibrates at ω1, one at θ_ω + π/2 at
// ω2; a wave at θ = θ_τ decays at 1/τ + Δ(1/τ)/2, one at θ_τ + π/2 at 1/τ − Δ(1/τ)/2.
// k is the angular gain as a gyro engineer quotes it (Bryan's factor, ≈ 0.28–0.3 for a hemisphere):
// the pattern on the shell precesses at −k·Ω, so in the frame of q at −2k·Ω, and the Coriolis term
// of the modal equations carries n·2k = 4k. (Written with "2k'" for the electrical gain, k' = 2k.)
//
// ## Averaging onto the slow variables (the demodulation convention)
// Slow variables u = (x1 + i·x2, x3 + i·x4) with the convention
//
//     q(t) = Re[u(t)·e^{iω0 t}],   q̇(t) = Re[iω0·u(t)·e^{iω0 t}],   ω0 = 2π·f0
//
// (equivalently u·e^{iω0t} = q − i·q̇/ω0: osculating variables; x1 = 2·LPF[q1·cos ω0t],
// x2 = −2·LPF[q1·sin ω0t], i.e. u = 2·LPF[q·e^{−iω0t}], plain complex down-conversion).
// The second relation asks Re[u̇·e^{iω0t}] = 0; the equation of motion then gives
// Re[iω0·u̇·e^{iω0t}] = g(t) := −Re[(iω0·D + K − ω0²I + 4kΩ·iω0·J)·u·e^{iω0t}]. Both together:
// u̇·e^{iω0t} is imaginary and u̇ = −(i/ω0)·g(t)·e^{−iω0t}, exactly. Averaging over a carrier period
// (⟨Re[w·e^{iω0t}]·e^{−iω0t}⟩ = w/2 for slow w) leaves, to first order in the small terms,
//
//     u̇ = [ −D/2 − 2kΩ·J + i·(K − ω0²I)/(2ω0) ]·u.
//
// With K − ω0²I = ω0·Δω·P(θ_ω) + (Δω²/4)·I (Δω = 2πΔf) and −J = iσy, this is model.md's
//   A = δ1·I + δ3·σz + δ4·σx + i·(δ5·σz + δ6·σx) + i·2Ωδ2·σy   with
//
//   δ1 = −1/τ                      δ2 = k
//   δ3 = −(Δ(1/τ)/2)·cos2θ_τ       δ4 = −(Δ(1/τ)/2)·sin2θ_τ
//   δ5 = π·Δf·cos2θ_ω              δ6 = π·Δf·sin2θ_ω
//
// with the split exact in the eigenvalues: the modes vibrate at ω0 ± Δω/2, so the slow modes turn
// at ±iΔω/2 exactly (the first-order average's i·Δω²/(8ω0)·I cancels at second order). What the
// averaging drops is O(|A|/ω0) (for f0 = 5 kHz, Δf = 0.1 Hz, Ω = 1 rad/s: |A|/ω0 ≈ 2e-5), and two
// second-order effects have no term in model.md's A (drivers/sim/README.md measures both):
//   - under rotation the two modes' mean frequency is exactly √(ω0² + (2kΩ)²) (undamped; whatever
//     the split: the roots of (ω1² − ω²)(ω2² − ω²) = (4kΩω)² sum to that), a common drift
//     ν ≈ (2kΩ)²/(2ω0) of the slow variables' phase (5.7e-6 rad/s at Ω = 1, 5 kHz);
//   - the Coriolis force acts at each mode's own frequency ω0 + s, not at ω0: a term
//     i·s·4kΩ·J/(2ω0) that turns the slow modes' shapes by ~kΩ·Δω/(ω0·|gap|), which C(ξ) and the
//     per-run x0 absorb (an "effective" ξ).
// f0 does not appear in δ: the map back needs it given.
//
// ## The pick-off path at the carrier
// A real pick-off path multiplies each channel's carrier by a gain and delays it; at the carrier a
// gain and a delay are one complex number (a delay τ multiplies u by e^{−iω0τ}). The two channels
// therefore see w = H·u with a complex 2×2 H. model.md's C(ξ) acts on u as
//
//     I + C(ξ) = | 1 + p   q   |,   p = ξ1 − i·ξ2,   q = ξ4 − i·ξ3,
//                | q     1 − p |
//
// and a common complex factor c (the chain's mean gain and delay) commutes with A, so it is
// absorbed by each run's initial state. A physical pick-off (channel gains and delays, cross-talk,
// a misplaced electrode) is a general complex H, two real numbers more than c·(I + C(ξ)) holds:
// pickoff_frame.hpp defines the physical errors (the nominal pick-off model, channel 1's electrode
// as the frame), derives what the model holds of them (ξ) and what it cannot (a complex frame angle
// that turns the anisotropies), and maps both ways. To first order
//
//   ξ1 = (1 − g)/2,  ξ2 = −Δφ/2,  ξ3 = κ,  ξ4 = ε/2   (g = g2/g1, Δφ = φ2 − φ1, ε channel 2's
//   electrode error: it sits at 90° − ε in the frame of q, 45° − ε/2 on the shell).
//
// Threads: stateless. Real-time: allocation-free.

#include <Eigen/Core>
#include <complex>
#include <string>

#include "hrgbench/estimator/parameters.hpp"

namespace hrgbench::estimator {

// The n = 2 working mode of the resonator (angles in the frame of q, see above).
struct ResonatorParameters {
  double frequency_hz = 5000.0;           // f0: mean of the two modes' frequencies, Hz
  double decay_time_s = 1000.0;           // τ: mean amplitude decay time, s (δ1 = −1/τ)
  double damping_anisotropy_per_s = 0.0;  // Δ(1/τ) = 1/τ1 − 1/τ2 ≥ 0, 1/s
  double damping_axis_rad = 0.0;          // θ_τ: the axis that decays at 1/τ + Δ(1/τ)/2
  double frequency_split_hz = 0.0;        // Δf = f1 − f2 ≥ 0, Hz
  double frequency_axis_rad = 0.0;        // θ_ω: the axis that vibrates at f0 + Δf/2
  double angular_gain = 0.3;              // k (Bryan's factor); = δ2

  // Quality factor of the mean mode, Q = π·f0·τ.
  double QualityFactor() const noexcept;
  // False with a reason when f0 ≤ 0, τ ≤ 0, Δf ∉ [0, f0), Δ(1/τ) < 0 or anything is not finite.
  bool IsValid(std::string* why) const;
};

// Errors of the pick-off path relative to channel 1 (pickoff_frame.hpp defines each; all zero =
// ideal).
struct PickoffParameters {
  double gain_ratio = 1.0;                 // g2/g1 > 0
  double phase_mismatch_rad = 0.0;         // φ2 − φ1 at the carrier, rad (channel 2 lags more)
  double cross_talk = 0.0;                 // κ: quadrature (90°) coupling between the channels
  double electrode_angle_error_rad = 0.0;  // ε: channel 2's electrode at 90° − ε (frame of q)

  bool IsValid(std::string* why) const;  // g > 0, |Δφ| < π, |ε| < π, finite
};

// δ from the resonator (f0 is not used: it does not enter δ).
Delta DeltaFromResonator(const ResonatorParameters& resonator) noexcept;
// The resonator from δ, with f0 given (δ1 must be < 0 for a finite τ). Canonical form: Δ(1/τ) ≥ 0,
// Δf ≥ 0, axes in (−π/2, π/2]; an axis whose anisotropy is zero is returned as 0.
ResonatorParameters ResonatorFromDelta(const Delta& delta, double frequency_hz) noexcept;

// I + C(ξ) as the complex 2×2 matrix acting on u (see above).
Eigen::Matrix2cd ComplexDistortion(const Xi& xi) noexcept;

// The oscillator's coefficients: q̈ + D·q̇ + K·q + coriolis·Ω·J·q̇ = 0 (coriolis = 4k), in SI units
// (rad/s, rad²/s²), for the mode frequencies scaled by `frequency_scale` (f(T)/f0, temperature).
struct OscillatorCoefficients {
  Eigen::Matrix2d damping;    // D, 1/s
  Eigen::Matrix2d stiffness;  // K, rad²/s²
  double coriolis = 0.0;      // 4k
};
OscillatorCoefficients OscillatorFromResonator(const ResonatorParameters& resonator,
                                               double frequency_scale = 1.0) noexcept;

}  // namespace hrgbench::estimator
