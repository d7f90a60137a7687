#include "hrgbench/estimator/summary.hpp"

#include <cmath>
#include <cstdio>

namespace hrgbench::estimator {

const char* ToString(Termination termination) noexcept {
  switch (termination) {
    case Termination::kNotRun:
      return "not run";
    case Termination::kConverged:
      return "converged";
    case Termination::kMaxIterations:
      return "max iterations";
    case Termination::kNoProgress:
      return "no progress";
    case Termination::kInvalidInput:
      return "invalid input";
    case Termination::kNotIdentifiable:
      return "not identifiable";
    case Termination::kNumericalFailure:
      return "numerical failure";
  }
  return "unknown";
}

namespace {

std::string Line(std::string_view name, std::string_view meaning, double value, double std_dev,
                 bool estimated) {
  char buffer[160];
  if (estimated && std::isfinite(std_dev)) {
    std::snprintf(buffer, sizeof buffer, "  %-7.*s %+.10e ± %.3e   %.*s\n",
                  static_cast<int>(name.size()), name.data(), value, std_dev,
                  static_cast<int>(meaning.size()), meaning.data());
  } else {
    std::snprintf(buffer, sizeof buffer, "  %-7.*s %+.10e %-11s   %.*s\n",
                  static_cast<int>(name.size()), name.data(), value,
                  estimated ? " (no std)" : " (held)", static_cast<int>(meaning.size()),
                  meaning.data());
  }
  return buffer;
}

}  // namespace

std::string EstimateSummary::Report() const {
  std::string out;
  char buffer[200];
  std::snprintf(buffer, sizeof buffer, "method %s: %s after %d iterations, %zu samples\n",
                method.c_str(), ToString(termination), iterations, samples_used);
  out += buffer;
  if (!message.empty()) out += "  " + message + "\n";
  for (int j = 0; j < 6; ++j)
    out += Line(kDeltaNames[j], kDeltaMeanings[j], delta[j], delta_std[j], delta_estimated[j]);
  for (int k = 0; k < 4; ++k)
    out += Line(kXiNames[k], kXiMeanings[k], xi[k], xi_std[k], xi_estimated[k]);
  std::snprintf(buffer, sizeof buffer, "  residual RMS %.4e (noise sigma estimate %.4e)\n",
                residual_rms, noise_sigma);
  out += buffer;
  for (std::size_t r = 0; r < residual_rms_per_run.size(); ++r) {
    std::snprintf(buffer, sizeof buffer, "    run %zu: residual RMS %.4e\n", r + 1,
                  residual_rms_per_run[r]);
    out += buffer;
  }
  if (!diagnostics.runs.empty()) {
    std::snprintf(buffer, sizeof buffer,
                  "  fit: %s; covariance %s; common phase degree %d per run%s\n",
                  diagnostics.Acceptable() ? "within its model" : "OUTSIDE ITS MODEL",
                  diagnostics.covariance_kind.c_str(), diagnostics.phase_degree,
                  diagnostics.omega_nuisance ? "; recorded rate uncertainties included" : "");
    out += buffer;
    for (const RunFitDiagnostics& d : diagnostics.runs) {
      std::snprintf(buffer, sizeof buffer,
                    "    run %d: residual/noise %.4f (limit %.4f), whiteness z %.2f, lag-1 "
                    "autocorrelation %+.3f, largest |r| %.1f sigma, %zu outliers removed\n",
                    d.run_id, d.residual_ratio, d.residual_ratio_threshold, d.whiteness_z,
                    d.lag1_autocorrelation, d.max_abs_residual_in_sigma, d.outliers_removed);
      out += buffer;
    }
  }
  if (!omega_sensitivity.empty()) {
    out +=
        "  Omega taken as exact: change of the estimate per 1e-06 rad/s error of a run's Omega\n";
    for (const OmegaSensitivity& o : omega_sensitivity) {
      std::snprintf(buffer, sizeof buffer, "    run %d:", o.run_id);
      out += buffer;
      for (int j = 0; j < 6; ++j) {
        if (!delta_estimated[j]) continue;
        std::snprintf(buffer, sizeof buffer, " %s %+.3e", kDeltaNames[j].data(), o.delta[j]);
        out += buffer;
      }
      for (int k = 0; k < 4; ++k) {
        if (!xi_estimated[k]) continue;
        std::snprintf(buffer, sizeof buffer, " %s %+.3e", kXiNames[k].data(), o.xi[k]);
        out += buffer;
      }
      out += "\n";
    }
  }
  for (const std::string& w : warnings) out += "  warning: " + w + "\n";
  return out;
}

}  // namespace hrgbench::estimator
