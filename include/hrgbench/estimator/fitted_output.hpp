#pragma once
// The fitted model of one run, evaluated at the run's own time stamps: what a report draws beside
// the data and subtracts from it for the residuals.
//
//   x̂(t) = e^{iψ(t)}·exp(A(Ω + ΔΩ, δ)·t)·x(0)      (slow variables, undistorted)
//   ŷ(t) = (I + C(ξ))·x̂(t)                          (the four channels as recorded)
//
// on u = (x1 + i·x2, x3 + i·x4), with δ, ξ from the summary and x(0), the common phase
// ψ(t) = Σ q_j·t^j and ΔΩ from summary.run_nuisance (the entry whose run_id is run.id); Ω is
// run.omega_rad_s. exp(A·t) is evaluated in closed form at every time stamp (no recurrence), so
// the result is the fit's own model to rounding: on the samples the fit used, the RMS of y − ŷ is
// summary.residual_rms_per_run (tested to 1e-9 relative).
//
// Pure functions: Eigen and the standard library, no I/O, thread-safe. They allocate the result.
// Failure: a summary without an entry for run.id (a method other than output error, or a run the
// fit did not see) or with non-finite δ/ξ gives an empty (0 × 4) matrix.

#include <Eigen/Core>

#include "hrgbench/estimator/run_data.hpp"
#include "hrgbench/estimator/summary.hpp"

namespace hrgbench::estimator {

// One row per sample: (ŷ1, ŷ2, ŷ3, ŷ4) at run.t_s[k].
using RunChannels = Eigen::Matrix<double, Eigen::Dynamic, 4>;

// ŷ at run.t_s (run.y is not read).
RunChannels FittedOutput(const EstimateSummary& summary, const RunData& run);

// x̂ at run.t_s: the model's slow variables before the pick-off distortion (for its orbit
// elements and principal forms, model.hpp's StateToOrbit and QuadraticForms).
RunChannels FittedState(const EstimateSummary& summary, const RunData& run);

}  // namespace hrgbench::estimator
