#pragma once
// The default estimator: output-error maximum likelihood of y(t) = (I + C(ξ))·exp(A(Ω, δ)·t)·x0
// over δ, any chosen subset of ξ, and one initial state x0 per run, under white Gaussian noise of
// equal variance on the four channels (so: nonlinear least squares of y).
//
// How:
//  1. Starting point without numerical differentiation: the integral equation-error form
//     r(t) − r(t0) = 2·Mδ(Ω, ∫r dt)·δ (trapezoid over the true time stamps), with the distortion's
//     first-order effect as Ω-proportional anisotropies to start ξ (see identifiability.hpp).
//  2. Identifiability check (identifiability.hpp): parameters the plan cannot determine are held at
//     their given values with a warning, or the estimate is refused (policy).
//  3. Levenberg–Marquardt on the exact model: exp(A·t) in closed form at every time stamp (so
//  dropped
//     samples and non-uniform time need nothing special), exact distortion, analytic Jacobian; the
//     per-run initial states are eliminated by a Schur complement, so the cost is linear in the
//     number of samples.
//  4. Covariance σ̂²·(JᵀJ)⁻¹ of δ and ξ with the initial states eliminated (the CRLB evaluated at
//  the
//     estimate), residual RMS per run and in total.
//
// Outside its own model (fit_diagnostics.hpp, docs/estimator/methods.md):
//  - per run, besides x0, a common phase ψ(t) = q_1·t + … + q_D·t^D of both channels is estimated
//    (phase_degree, default 2), so the estimate does not depend on what the demodulation
//    reference's phase and frequency do (a constant offset and a ramp of the frequency);
//  - each run's Ω is a nuisance with a Gaussian prior of its recorded standard error
//    (RunData::omega_std_rad_s), so the uncertainty of Ω is in the reported std, and a recorded Ω
//    the data contradict is reported;
//  - samples whose residual exceeds outlier_threshold_sigma robust σ are removed and the fit
//    repeated (stated in the diagnostics and the warnings);
//  - the residuals are checked against the model-free noise and for whiteness; coloured residuals
//    switch the reported covariance to the sandwich form; every failed check is a warning and is
//    listed in diagnostics.problems, which the bench's verdict judges.

#include <array>
#include <string>
#include <vector>

#include "hrgbench/estimator/identifiability.hpp"
#include "hrgbench/estimator/noise_shape.hpp"
#include "hrgbench/estimator/run_data.hpp"
#include "hrgbench/estimator/run_set.hpp"
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
  // Which δ components to estimate; the others are held at delta_fixed. δ2 is held automatically
  // when no run has Ω ≠ 0 (policy kFix), at delta_fixed[kScaleFactor].
  std::array<bool, 6> delta_estimated = {true, true, true, true, true, true};
  Delta delta_fixed = (Delta() << 0.0, 0.3, 0.0, 0.0, 0.0, 0.0).finished();

  UnidentifiablePolicy unidentifiable = UnidentifiablePolicy::kFix;
  IdentifiabilityOptions identifiability;

  // Levenberg–Marquardt. The start from the integral equation error is within a few per cent, so a
  // handful of iterations is typical; 50 is a safety bound.
  int max_iterations = 50;
  // Stop when every scaled step component is below this (scaled by the parameter's std, so 1e-6
  // means "moved less than a millionth of its own uncertainty").
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

  // Degree D of the per-run common phase nuisance ψ(t) = q_1·t + … + q_D·t^D (0 … 3): 0 = the
  // demodulation reference is taken as exactly the resonator's phase, 1 adds a constant frequency
  // offset per run, 2 a frequency ramp.
  int phase_degree = 2;
  // Start each run's common phase from the data (the orbit phase of data and model,
  // src/estimator/common_phase_start.hpp) rather than at zero. A run whose reference is off by
  // 0.06 rad/s has turned by 6 rad at 100 s: from zero, long runs with an offset and a drift land
  // in a wrong basin (docs/estimator/convergence.md). false only to show that failure.
  bool common_phase_start_from_data = true;
  // Each run's Ω as a nuisance parameter with a prior of RunData::omega_std_rad_s (runs without a
  // finite positive std keep their Ω exact).
  bool omega_uncertainty = true;
  // Remove samples with a residual beyond this many robust σ on any channel and fit again (at most
  // max_outlier_passes times); 0 = keep every sample.
  double outlier_threshold_sigma = 8.0;
  int max_outlier_passes = 2;
  // Lags of the whiteness statistic.
  int whiteness_lags = 20;
  // The pick-off noise's shape as the station declares it (noise_shape.hpp; white by default): the
  // model-free noise estimate, the whiteness null and the covariance follow it.
  NoiseShape noise_shape;
  enum class Covariance {
    kAuto,      // white-noise covariance, or the sandwich when a run's residuals are not white or
                // the declared noise is coloured
    kWhite,     // always σ̂²·(JᵀJ)⁻¹
    kSandwich,  // always the sandwich
  };
  Covariance covariance = Covariance::kAuto;
  FitQualityLimits fit_quality;

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
// The same on runs read run by run (run_set.hpp): each pass over the data loads a run for its
// turn, so a set that keeps nothing between loads bounds the fit's memory by the runs in use
// (one per thread) instead of the session.
EstimateSummary EstimateMaximumLikelihood(const RunSet& runs, const MlOptions& options = {});

// The starting-point method on its own (no ML refinement): equation error in integral form, no
// numerical differentiation. Estimates δ and, when the plan allows, the ξ in `xi_estimated` through
// their first-order effect.
EstimateSummary EstimateIntegralEquationError(const std::vector<RunData>& runs,
                                              const MlOptions& options = {});

}  // namespace hrgbench::estimator
