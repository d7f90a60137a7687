#pragma once
// The compensation set p of the paper's u = V(y, p): what the gyro's electronics hold of a unit's
// estimate to run it as a whole-angle gyro (docs/estimator/operating-mode.md).
//
//   - ξ̂: the pick-off's inverse, x̂ = (I + C(ξ̂))⁻¹·y before any form, angle or loop error is read;
//   - δ̂2: the angular gain, Ω̂ = −(θ̂' − d̂(θ̂)) / (2·δ̂2);
//   - δ̂3, δ̂4: the damping anisotropy's drift of the wave, d̂(θ) = δ̂4·cos2θ − δ̂3·sin2θ, removed
//     from the rate;
//   - δ̂1, δ̂5, δ̂6: the amplitude and quadrature loops' feed-forward (the decay the energy loop
//     makes up, the frequency split the quadrature loop cancels as the wave turns).
//
// Everything is in the model's frame (pickoff_frame.hpp): the frame the fit's δ and ξ are in is the
// frame the electronics read the angle in once they apply (I + C(ξ̂))⁻¹, so the fit's δ̂ are the
// right ones whatever the frame's angle to channel 1's electrode.
//
// Pure functions, Eigen and the standard library only, noexcept.

#include <Eigen/Core>
#include <array>

#include "hrgbench/estimator/parameters.hpp"
#include "hrgbench/estimator/summary.hpp"

namespace hrgbench::estimator {

// p's parameters in one vector: δ1…δ6 then ξ1…ξ4.
inline constexpr int kCompensationSize = 10;
using CompensationVector = Eigen::Matrix<double, kCompensationSize, 1>;
using CompensationCovariance = Eigen::Matrix<double, kCompensationSize, kCompensationSize>;

struct CompensationSet {
  Delta delta = Delta::Zero();
  Xi xi = Xi::Zero();
  // Which entries come from an estimate; the others are nominal values the electronics assume
  // (an identity compensation: none). Their rows and columns of `covariance` are zero: a nominal
  // value's error is not known here, and is named by this flag, not hidden in a zero std.
  std::array<bool, kCompensationSize> estimated{};
  CompensationCovariance covariance = CompensationCovariance::Zero();

  CompensationVector AsVector() const;
};

// What an untuned unit's electronics run with: no pick-off inverse, no drift removed, the design's
// angular gain and decay, no split fed forward.
CompensationSet IdentityCompensation(double nominal_angular_gain, double nominal_damping_per_s);

// p from a session's estimate: every estimated δ and ξ with the estimate's covariance; a component
// the fit held keeps the value it was held at, flagged as not estimated. Returns false (and leaves
// `out` unchanged) when the estimate is not usable or δ2 is not a finite non-zero number.
bool CompensationFromEstimate(const EstimateSummary& estimate, CompensationSet* out) noexcept;

// The angle-dependent rate error a compensation leaves, to first order, on a wave turning under a
// constant rate Ω: its first harmonic c·cos2θ + s·sin2θ (θ the electrical wave angle) has
//
//   c = −Δδ4/(2δ2) − 2Ω·Δξ1,   s = +Δδ3/(2δ2) − 2Ω·Δξ4,   Δ = truth − p,
//
// (operating-mode.md "The rate error a compensation leaves"). Returns the 2×10 Jacobian of (c, s)
// with respect to p's vector (so the prediction's covariance is J·Σ·Jᵀ); δ2 is p's.
Eigen::Matrix<double, 2, kCompensationSize> AngleDependentRateErrorJacobian(
    const CompensationSet& p, double omega_rad_s) noexcept;

// The prediction itself: the covariance of (c, s) from p's covariance, rad²/s².
Eigen::Matrix2d PredictedAngleDependentRateErrorCovariance(const CompensationSet& p,
                                                           double omega_rad_s) noexcept;

}  // namespace hrgbench::estimator
