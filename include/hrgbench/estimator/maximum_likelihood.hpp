#pragma once
// The default estimator: output-error maximum likelihood of y(t) = (I + C(ξ))·exp(A(Ω, δ)·t)·x0 over δ,
// any chosen subset of ξ, and one initial state x0 per run, under white Gaussian noise of equal
// variance on the four channels (so: nonlinear least squares of y).
//
// How:
//  1. Starting point without numerical differentiation: the integral equation-error form
//     r(t) − r(t0) = 2·Mδ(Ω, ∫r dt)·δ (trapezoid over the true time stamps), with the distortion's
//     first-order effect as Ω-proportional anisotropies to start ξ (see identifiability.hpp).
//  2. Identifiability check (identifiability.hpp): parameters the plan cannot determine are held at
//     their given values with a warning, or the estimate is refused (policy).
//  3. Levenberg–Marquardt on the exact model: exp(A·t) in closed form at every time stamp (so dropped
//     samples and non-uniform time need nothing special), exact distortion, analytic Jacobian; the
//     per-run initial states are eliminated by a Schur complement, so the cost is linear in the
//     number of samples.
//  4. Covariance σ̂²·(JᵀJ)⁻¹ of δ and ξ with the initial states eliminated (the CRLB evaluated at the
//     estimate), residual RMS per run and in total.

#include <array>
#include <string>
#include <vector>

#include "hrgbench/estimator/identifiability.hpp"
#include "hrgbench/estimator/run_data.hpp"
#include "hrgbench/estimator/summary.hpp"

namespace hrgbench::estimator {

enum class UnidentifiablePolicy {
  kFix,     // hold what cannot be determined at its given value, estimate the rest, warn
  kRefuse,  // return kNotIdentifiable without estimating anything
};

struct MlOptions {
  // Which ξ components to estimate; the others are held at xi_fixed.
  XiMask xi_estimated = kAllXi;
  Xi xi_fixed = Xi::Zero();
  // Which δ components to estimate; the others are held at delta_fixed. δ2 is held automatically when
  // no run has Ω ≠ 0 (policy kFix), at delta_fixed[kScaleFactor].
  std::array<bool, 6> delta_estimated = {true, true, true, true, true, true};
  Delta delta_fixed = (Delta() << 0.0, 0.3, 0.0, 0.0, 0.0, 0.0).finished();

  UnidentifiablePolicy unidentifiable = UnidentifiablePolicy::kFix;
  IdentifiabilityOptions identifiability;

  // Levenberg–Marquardt. The start from the integral equation error is within a few per cent, so a
  // handful of iterations is typical; 50 is a safety bound.
  int max_iterations = 50;
  // Stop when every scaled step component is below this (scaled by the parameter's std, so 1e-6 means
  // "moved less than a millionth of its own uncertainty").
  double step_tolerance_in_std = 1e-6;
  // ... or when the relative cost decrease is below this.
  double cost_tolerance = 1e-15;
  double initial_damping = 1e-6;  // λ of Marquardt, relative to the scaled diagonal

  // Threads for the passes over the data (runs are spread over them): 0 = every hardware thread,
  // 1 = single-threaded, no thread created (embedded targets). Small problems run single-threaded.
  int num_threads = 0;
  // ... but only when the runs hold at least this many samples: below ~20k a pass over the data
  // takes about a millisecond and starting threads costs more than it saves.
  std::size_t min_samples_for_threads = 20000;

  // Optional starting point; when not set the integral equation error supplies it.
  bool use_initial_guess = false;
  Delta initial_delta = Delta::Zero();
  Xi initial_xi = Xi::Zero();

  bool IsValid(std::string* why) const;
};

// Minimum samples per run: 2 (four channels per sample, four unknowns of x0 per run).
inline constexpr int kMlMinimumSamples = 2;

EstimateSummary EstimateMaximumLikelihood(const std::vector<RunData>& runs,
                                          const MlOptions& options = {});

// The starting-point method on its own (no ML refinement): equation error in integral form, no
// numerical differentiation. Estimates δ and, when the plan allows, the ξ in `xi_estimated` through
// their first-order effect.
EstimateSummary EstimateIntegralEquationError(const std::vector<RunData>& runs,
                                              const MlOptions& options = {});

}  // namespace hrgbench::estimator
