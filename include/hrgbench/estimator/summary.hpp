#pragma once
// What every estimator returns: Options in, Summary out. A default-constructed summary says the
// estimator was not called; every estimator fills in all fields, including on failure.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "hrgbench/estimator/fit_diagnostics.hpp"
#include "hrgbench/estimator/parameters.hpp"

namespace hrgbench::estimator {

// What an output-error fit estimated for one run besides (δ, ξ): the per-run nuisance parameters.
// With them and the summary's δ and ξ the fitted output of the run can be evaluated
// (fitted_output.hpp): ŷ(t) = e^{iψ(t)}·(I + C(ξ))·exp(A(Ω + ΔΩ, δ)·t)·x(0) on u = (y1 + i·y2,
// y3 + i·y4), ψ(t) = Σ_j q_j·t^j (MaximumLikelihood's header says why each is there).
struct RunNuisanceEstimate {
  int run_id = 0;  // RunData::id of the run it belongs to
  // x(0), the true (undistorted) initial state; equals initial_states[r].
  Eigen::Vector4d initial_state = Eigen::Vector4d::Constant(kNaN);
  // q_1 … q_D of the common phase, rad/s^j; empty when the fit had no common phase (D = 0).
  std::vector<double> phase_coefficients;
  // ΔΩ: the fitted offset of the run's rate from the recorded Ω, rad/s; 0 when Ω was held exact.
  double omega_offset_rad_s = 0.0;
};

// A 1e-6 rad/s error of a run's Ω: the step the sensitivities below are given for (a good rate
// table's calibration; the 1e-5 relative error at 0.3 rad/s is 3e-6).
inline constexpr double kOmegaSensitivityStepRadS = 1e-6;

// What an error of one run's Ω would do to the estimate, for a run whose Ω the fit took as exact
// (no finite recorded standard error, or MlOptions::omega_uncertainty off): the change of each
// estimated component were the recorded Ω off by kOmegaSensitivityStepRadS, i.e.
// ∂θ/∂Ω_r·1e-6, linearised at the estimate with every other run's Ω held and every nuisance
// re-fitted. NaN for components held fixed. Same units as delta and xi.
struct OmegaSensitivity {
  int run_id = 0;
  Delta delta = Delta::Constant(kNaN);
  Xi xi = Xi::Constant(kNaN);
};

enum class Termination {
  kNotRun,            // the estimator was not called
  kConverged,         // a convergence tolerance was met (or a direct method solved its system)
  kMaxIterations,     // stopped at max_iterations; the estimate is the best one found
  kNoProgress,        // the damped step could not reduce the cost further above rounding level
  kInvalidInput,      // options or data rejected before any computation; see message
  kNotIdentifiable,   // the run plan cannot determine the requested parameters and the policy
                      // says refuse; see message and warnings
  kNumericalFailure,  // a singular system or a non-finite value appeared; see message
};

const char* ToString(Termination termination) noexcept;

struct EstimateSummary {
  std::string method = "none";
  Termination termination = Termination::kNotRun;
  std::string message = "Estimate was not called";

  // The estimate. Components held fixed carry the value they were held at, and NaN std.
  Delta delta = Delta::Constant(kNaN);
  Delta delta_std = Delta::Constant(kNaN);
  std::array<bool, 6> delta_estimated = {false, false, false, false, false, false};
  Xi xi = Xi::Constant(kNaN);
  Xi xi_std = Xi::Constant(kNaN);
  XiMask xi_estimated = kNoXi;

  // Covariance of the estimated components, ordered as δ (estimated ones, in index order) then ξ
  // (estimated ones). For maximum likelihood: σ̂²·(JᵀJ)⁻¹ with the per-run nuisance parameters
  // eliminated, or the sandwich covariance when the residuals are coloured
  // (diagnostics.covariance_kind says which).
  Eigen::MatrixXd covariance;

  // Initial state x(0) of each run (output-error methods only; empty otherwise).
  std::vector<Eigen::Vector4d> initial_states;
  // Every per-run nuisance estimate, one per run in the order of the runs given (output-error
  // methods only; empty otherwise): what FittedOutput needs to draw a run's fitted model.
  std::vector<RunNuisanceEstimate> run_nuisance;

  // Residual RMS. Output-error methods: of y, per channel and sample (same unit as y).
  // Equation-error methods: of the equation (dz/dt or the integral form), a diagnostic only.
  std::vector<double> residual_rms_per_run;
  double residual_rms = kNaN;
  double noise_sigma = kNaN;  // σ̂ from the residuals, corrected for the degrees of freedom

  // Output-error methods: is the fit right? Model-free noise, residual ratio, whiteness, outliers,
  // per run, and the checks that failed (see fit_diagnostics.hpp). Empty for the other methods.
  FitDiagnostics diagnostics;

  // Maximum likelihood: one entry per run whose Ω was taken as exact, in the order of the runs
  // (empty when every Ω entered with its uncertainty, and for the other methods). The std above
  // do not include Ω's error for these runs; a warning says so.
  std::vector<OmegaSensitivity> omega_sensitivity;

  int iterations = 0;
  std::size_t samples_used = 0;
  int threads_used = 1;  // threads the passes over the data ran on (the caller's included)
  std::vector<std::string> warnings;

  bool IsUsable() const {
    return termination == Termination::kConverged || termination == Termination::kMaxIterations ||
           termination == Termination::kNoProgress;
  }
  bool Converged() const { return termination == Termination::kConverged; }

  // A readable multi-line report: method, termination, every parameter with ± one std, residuals
  // and warnings.
  std::string Report() const;
};

}  // namespace hrgbench::estimator
