#pragma once
// The compensation set p of the paper's u = V(y, p): what the gyro's electronics hold of a unit's
// estimate to run it as a whole-angle gyro (docs/estimator/operating-mode.md).
//
//   - ξ̂: the pick-off's inverse, x̂ = (I + C(ξ̂))⁻¹·y before any form, angle or loop error is read;
//   - δ̂2: the angular gain, Ω̂ = −(θ̂' − d̂(θ̂)) / (2·δ̂2);
//   - δ̂3, δ̂4: the damping anisotropy's drift of the wave, d̂(θ) = δ̂4·cos2θ − δ̂3·sin2θ, removed
//     from the rate;
//   - δ̂1, δ̂5, δ̂6: the amplitude and quadrature loops' feed-forward (the decay the energy loop
//     makes up, the frequency split the quadrature loop cancels as the wave turns);
//   - b̂: a rate bias removed from Ω̂, which free runs cannot see (the forcers' frame turned from the
//     pick-off's: operating-mode.md term 5); 0 until a verification on the table measures it.
//
// A verification at constant rates of both signs refines what free runs cannot see
// (RefineCompensation): the forcers' gain and angle drift the wave like a damping anisotropy times
// the energy loop's effort, so δ̂3, δ̂4 become the operating mode's, and b̂ its bias.
//
// Everything is in the model's frame (pickoff_frame.hpp): the frame the fit's δ and ξ are in is the
// frame the electronics read the angle in once they apply (I + C(ξ̂))⁻¹, so the fit's δ̂ are the
// right ones whatever the frame's angle to channel 1's electrode.
//
// Pure functions, Eigen and the standard library only, noexcept.

#include <Eigen/Core>
#include <array>
#include <span>

#include "hrgbench/estimator/parameters.hpp"
#include "hrgbench/estimator/summary.hpp"

namespace hrgbench::estimator {

// p's parameters in one vector: δ1…δ6, ξ1…ξ4, then b̂ (rad/s).
inline constexpr int kCompensationSize = 11;
inline constexpr int kCompensationXi = 6;     // index of ξ1
inline constexpr int kCompensationBias = 10;  // index of b̂
using CompensationVector = Eigen::Matrix<double, kCompensationSize, 1>;
using CompensationCovariance = Eigen::Matrix<double, kCompensationSize, kCompensationSize>;

struct CompensationSet {
  Delta delta = Delta::Zero();
  Xi xi = Xi::Zero();
  double rate_bias_rad_s = 0.0;  // b̂, subtracted from Ω̂
  // Which entries come from an estimate; the others are nominal values the electronics assume
  // (an identity compensation: none). Their rows and columns of `covariance` are zero: a nominal
  // value's error is not known here, and is named by this flag, not hidden in a zero std.
  std::array<bool, kCompensationSize> estimated{};
  CompensationCovariance covariance = CompensationCovariance::Zero();

  CompensationVector AsVector() const;
};

// The values of a vector in AsVector's order (a block the electronics hold, read back): nothing in
// it is flagged as estimated and its covariance is zero.
CompensationSet CompensationFromVector(const CompensationVector& values) noexcept;

// What an untuned unit's electronics run with: no pick-off inverse, no drift removed, the design's
// angular gain and decay, no split fed forward.
CompensationSet IdentityCompensation(double nominal_angular_gain, double nominal_damping_per_s);

// p from a session's estimate: every estimated δ and ξ with the estimate's covariance; a component
// the fit held keeps the value it was held at, flagged as not estimated. Returns false (and leaves
// `out` unchanged) when the estimate is not usable or δ2 is not a finite non-zero number.
bool CompensationFromEstimate(const EstimateSummary& estimate, CompensationSet* out) noexcept;

// The rate error a compensation leaves, to first order, on a wave turning under a constant rate Ω:
// a bias b and the first harmonic c·cos2θ + s·sin2θ (θ the electrical wave angle) with
//
//   b = (δ2/δ̂2 − 1)·Ω − Δb̂,   c = −Δδ4/(2δ2) − 2Ω·Δξ1,   s = +Δδ3/(2δ2) − 2Ω·Δξ4,
//
// Δ = truth − p (operating-mode.md "The rate error a compensation leaves"). Returns the 3×11
// Jacobian of (b, c, s) with respect to p's vector, so the prediction's covariance is J·Σ·Jᵀ; δ2 is
// p's.
using RateErrorJacobian = Eigen::Matrix<double, 3, kCompensationSize>;
RateErrorJacobian CompensationRateErrorJacobian(const CompensationSet& p,
                                                double omega_rad_s) noexcept;

// The prediction itself: the covariance of (b, c, s) from p's covariance, rad²/s².
Eigen::Matrix3d PredictedRateErrorCovariance(const CompensationSet& p, double omega_rad_s) noexcept;

// One constant-rate hold of a verification, read with p: the bias and the first harmonic of 2θ of
// Ω̂ − Ω (analysis::FitRateErrorHarmonics), each with its std.
struct VerificationHold {
  double omega_rad_s = 0.0;
  double bias_rad_s = 0.0, bias_std_rad_s = 0.0;
  double cos_rad_s = 0.0, cos_std_rad_s = 0.0;
  double sin_rad_s = 0.0, sin_std_rad_s = 0.0;
};

// What the holds say, fitted against Ω by weighted least squares (operating-mode.md "What free runs
// cannot see"): each of c, s and the bias as an intercept (what does not scale with Ω: drift and
// bias) plus a slope (what does: −2Δξ1, −2Δξ4 and the scale factor's error δ2/δ̂2 − 1).
// The intercepts replace p's δ̂3, δ̂4 and b̂ (the operating mode's drift and bias, which free runs
// cannot see); the slopes measure ξ1, ξ4 and δ2 again, independently of the free runs, and are
// combined with p's by a linear update (p's correlated entries follow), so the refined p uses both.
struct CompensationRefinement {
  CompensationSet refined;
  // The slopes as measurements of p's errors: Δξ1, Δξ4 and δ2/δ̂2 − 1, with their std (a check of
  // the free runs against the table: each within a few std of zero).
  Eigen::Vector3d slope_check = Eigen::Vector3d::Zero();
  Eigen::Vector3d slope_check_std = Eigen::Vector3d::Zero();
};

// Needs holds at two distinct rates at least, every std finite and positive, p's δ2 non-zero;
// returns false otherwise (`out` unchanged).
bool RefineCompensation(const CompensationSet& p, std::span<const VerificationHold> holds,
                        CompensationRefinement* out) noexcept;

}  // namespace hrgbench::estimator
