#pragma once
// The --json output of hrg-estimate: ONE object, stable keys, for scripts and the comparison tool.
//
//   method               string   "ml" | "paper" | "paper-xi-grid"
//   delta                [6]      estimate (held components: the value held)
//   delta_std            [6]      one std; null where not estimated
//   xi                   [4]      estimate; null where the method has no value for it
//   xi_std               [4]      one std; null where not estimated
//   residual_rms         number   (null if not computed)
//   converged            bool
//   warnings             [string] selection, session and estimator warnings, in that order
//   termination          string   estimator::ToString(Termination)
//   message              string   the estimator's one-line message
//   iterations           int
//   samples_used         int
//   residual_rms_per_run [number]
//   noise_sigma          number   σ̂ from the residuals (null if not computed)
//   fit                  object   is the fit right? (output-error methods; null otherwise):
//                                 {acceptable, problems [string], covariance ("white"|"sandwich"),
//                                  sandwich_batch_samples, sandwich_to_white_std_max, phase_degree,
//                                  omega_nuisance, limits {residual_ratio_max, whiteness_z_max,
//                                  omega_offset_max_in_std}, runs [{run, samples, noise_sigma,
//                                  residual_rms, residual_ratio, residual_ratio_threshold,
//                                  lag1_autocorrelation,
//                                  whiteness_lags, whiteness_q, whiteness_z,
//                                  max_abs_residual_in_sigma, excess_kurtosis, outliers_removed,
//                                  largest_outlier_in_sigma, common_frequency_rad_s,
//                                  common_frequency_drift_rad_s2, omega_offset_rad_s,
//                                  omega_offset_data_rad_s, omega_offset_in_std,
//                                  noise_free}]}
//   engineering          object   the estimate in the field's units (engineering_quantities.hpp):
//                                 {frequency_hz (f0 from the record, null if not recorded),
//                                  frequency_source, quantities [{name, label, unit, value, std,
//                                  determined, note}] in the estimator's order}
//   truth                object   only when the session has "simulation": {delta, xi, sigma, seed}
//   omega_sensitivity    object   only when some run's Ω was taken as exact (no recorded std):
//                                 {omega_taken_as_exact: true, step_rad_s: 1e-6, runs [{run,
//                                  delta [6], xi [4]}]}: the change of each estimated component
//                                 per 1e-6 rad/s error of that run's Ω (null for held ones)
//   preparation          object   added by hrg-estimate and the estimate of record (not by
//                                 EstimateReportJson): what was done to the record's samples
//                                 before the fit, bench/recorded_runs.hpp PreparedRuns::Json()
//                                 {iq_convention, release_settling {output_filter, fraction,
//                                  settle_s, runs [{run, samples_skipped, first_fitted_t_s}]},
//                                  notes [string]}
//
// JSON has no NaN: every non-finite number is written as null.

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "hrgbench/estimator/engineering_quantities.hpp"
#include "hrgbench/estimator/summary.hpp"
#include "hrgbench/session/session_record.hpp"

namespace hrgbench::bench {

// The keys every report has ("truth" is optional and not listed).
inline constexpr std::string_view kReportKeys[] = {"method",
                                                   "delta",
                                                   "delta_std",
                                                   "xi",
                                                   "xi_std",
                                                   "residual_rms",
                                                   "converged",
                                                   "warnings",
                                                   "termination",
                                                   "message",
                                                   "iterations",
                                                   "samples_used",
                                                   "residual_rms_per_run",
                                                   "noise_sigma",
                                                   "fit",
                                                   "engineering"};

// The "fit" object alone (null when the summary has no diagnostics).
nlohmann::json FitDiagnosticsJson(const estimator::EstimateSummary& summary);

// The "engineering" object alone, from quantities computed with f0 from `frequency_source`.
nlohmann::json EngineeringJson(const estimator::EngineeringQuantities& engineering,
                               std::string_view frequency_source);

// `warnings` are the caller's (method selection, session reading), put before the estimator's.
// `record` is the session's record (session::ReadSessionRecord): it gives the engineering
// quantities' f0 and pick-off declaration, and its "simulation" block, if any, "truth".
nlohmann::json EstimateReportJson(std::string_view method,
                                  const estimator::EstimateSummary& summary,
                                  const std::vector<std::string>& warnings,
                                  const session::SessionRecord& record);

// A number, or null when not finite.
nlohmann::json NumberOrNull(double value);

// The estimate of record's per-run nuisance (summary.run_nuisance), recorded as outcome.estimate
// "fitted_runs" by EstimateRecordedSession (not by EstimateReportJson: hrg-estimate --json keeps
// its keys): [{run, initial_state [4], phase_coefficients [q_1 … q_D, rad/s^j],
// omega_offset_rad_s}]. With δ and ξ it is the fitted model of each run (fitted_output.hpp), so the
// report draws the recorded fit without re-running it. Numbers are written in shortest round-trip
// form, so the model drawn is the fit's own to the last bit. Empty array for a method without
// nuisance (the paper's).
nlohmann::json FittedRunsJson(const estimator::EstimateSummary& summary);

}  // namespace hrgbench::bench
