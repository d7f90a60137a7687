#include "hrgbench/analysis/estimate_report_json.hpp"

#include <cmath>

#include "hrgbench/analysis/engineering_of_record.hpp"
#include "hrgbench/analysis/recorded_frequency.hpp"

namespace hrgbench::bench {
namespace {

template <typename Vector>
nlohmann::json Numbers(const Vector& v) {
  nlohmann::json array = nlohmann::json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) array.push_back(NumberOrNull(v(i)));
  return array;
}

// A std is reported only for estimated components: a held one has no uncertainty from this fit.
template <typename Vector, typename Mask>
nlohmann::json Stds(const Vector& v, const Mask& estimated) {
  nlohmann::json array = nlohmann::json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    array.push_back(estimated[static_cast<std::size_t>(i)] ? NumberOrNull(v(i)) : nlohmann::json());
  }
  return array;
}

// The simulator's truth (session_record.hpp: "simulation" is the simulator's, passed through).
nlohmann::json Truth(const nlohmann::json& simulation) {
  if (!simulation.is_object()) return nullptr;
  nlohmann::json truth = nlohmann::json::object();
  for (const char* key : {"delta", "xi", "sigma", "seed"}) {
    if (simulation.contains(key)) truth[key] = simulation[key];
  }
  return truth;
}

}  // namespace

nlohmann::json NumberOrNull(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json();
}

nlohmann::json FitDiagnosticsJson(const estimator::EstimateSummary& summary) {
  const estimator::FitDiagnostics& d = summary.diagnostics;
  if (d.runs.empty()) return nullptr;
  nlohmann::json runs = nlohmann::json::array();
  for (const estimator::RunFitDiagnostics& r : d.runs) {
    runs.push_back({
        {"run", r.run_id},
        {"noise_free", r.noise_free},
        {"samples", r.samples},
        {"noise_sigma", NumberOrNull(r.noise_sigma)},
        {"residual_rms", NumberOrNull(r.residual_rms)},
        {"residual_ratio", NumberOrNull(r.residual_ratio)},
        {"residual_ratio_threshold", NumberOrNull(r.residual_ratio_threshold)},
        {"lag1_autocorrelation", NumberOrNull(r.lag1_autocorrelation)},
        {"whiteness_lags", r.whiteness_lags},
        {"whiteness_q", NumberOrNull(r.whiteness_q)},
        {"whiteness_z", NumberOrNull(r.whiteness_z)},
        {"max_abs_residual_in_sigma", NumberOrNull(r.max_abs_residual_in_sigma)},
        {"excess_kurtosis", NumberOrNull(r.excess_kurtosis)},
        {"outliers_removed", r.outliers_removed},
        {"largest_outlier_in_sigma", NumberOrNull(r.largest_outlier_in_sigma)},
        {"common_frequency_rad_s", NumberOrNull(r.common_frequency_rad_s)},
        {"common_frequency_drift_rad_s2", NumberOrNull(r.common_frequency_drift_rad_s2)},
        {"omega_offset_rad_s", NumberOrNull(r.omega_offset_rad_s)},
        {"omega_offset_data_rad_s", NumberOrNull(r.omega_offset_data_rad_s)},
        {"omega_offset_in_std", NumberOrNull(r.omega_offset_in_std)},
    });
  }
  nlohmann::json problems = nlohmann::json::array();
  for (const std::string& p : d.problems) problems.push_back(p);
  return {
      {"acceptable", d.Acceptable()},
      {"problems", problems},
      {"covariance", d.covariance_kind},
      {"noise_shape", d.noise_shape},
      {"difference_stride", d.difference_stride},
      {"whiteness_first_lag", d.whiteness_first_lag},
      {"sandwich_batch_samples", d.sandwich_batch_samples},
      {"sandwich_to_white_std_max", NumberOrNull(d.sandwich_to_white_std_max)},
      {"phase_degree", d.phase_degree},
      {"omega_nuisance", d.omega_nuisance},
      {"limits",
       {{"residual_ratio_max", d.limits.residual_ratio_max},
        {"whiteness_z_max", d.limits.whiteness_z_max},
        {"omega_offset_max_in_std", d.limits.omega_offset_max_in_std}}},
      {"runs", runs},
  };
}

nlohmann::json EngineeringJson(const estimator::EngineeringQuantities& engineering,
                               std::string_view frequency_source) {
  nlohmann::json quantities = nlohmann::json::array();
  for (std::size_t k = 0; k < estimator::kEngineeringQuantityCount; ++k) {
    const estimator::EngineeringQuantityInfo& info = estimator::kEngineeringQuantities[k];
    const estimator::EngineeringValue& v = engineering.values[k];
    nlohmann::json budget = nlohmann::json::array();
    for (const estimator::UncertaintyComponent& c : v.budget) {
      budget.push_back({{"source", c.source},
                        {"standard_uncertainty", NumberOrNull(c.standard_uncertainty)},
                        {"type", c.systematic ? "B" : "A"},
                        {"note", c.note}});
    }
    quantities.push_back({{"name", std::string(info.name)},
                          {"label", std::string(info.label)},
                          {"unit", std::string(info.unit)},
                          {"value", NumberOrNull(v.value)},
                          {"std", NumberOrNull(v.std)},
                          {"statistical_std", NumberOrNull(v.statistical_std)},
                          {"determined", v.determined},
                          {"note", v.note},
                          {"budget", budget}});
  }
  nlohmann::json limitations = nlohmann::json::array();
  for (const std::string& l : engineering.limitations) limitations.push_back(l);
  return {
      {"frequency_hz", NumberOrNull(engineering.frequency_hz)},
      {"frequency_source", std::string(frequency_source)},
      {"coverage_factor", engineering.coverage_factor},
      {"relative_frequency_rate_per_s", NumberOrNull(engineering.relative_frequency_rate_per_s)},
      {"cross_talk_stage", estimator::ToString(engineering.cross_talk_stage)},
      {"pickoff_frame_angle_rad",
       {NumberOrNull(engineering.pickoff_frame_angle_rad.real()),
        NumberOrNull(engineering.pickoff_frame_angle_rad.imag())}},
      {"limitations", limitations},
      {"quantities", quantities}};
}

nlohmann::json EstimateReportJson(std::string_view method,
                                  const estimator::EstimateSummary& summary,
                                  const std::vector<std::string>& warnings,
                                  const session::SessionRecord& record) {
  nlohmann::json all_warnings = nlohmann::json::array();
  for (const std::string& w : warnings) all_warnings.push_back(w);
  for (const std::string& w : summary.warnings) all_warnings.push_back(w);

  nlohmann::json per_run = nlohmann::json::array();
  for (double rms : summary.residual_rms_per_run) per_run.push_back(NumberOrNull(rms));

  nlohmann::json report = {
      {"method", std::string(method)},
      {"delta", Numbers(summary.delta)},
      {"delta_std", Stds(summary.delta_std, summary.delta_estimated)},
      {"xi", Numbers(summary.xi)},
      {"xi_std", Stds(summary.xi_std, summary.xi_estimated)},
      {"residual_rms", NumberOrNull(summary.residual_rms)},
      {"converged", summary.Converged()},
      {"warnings", all_warnings},
      {"termination", estimator::ToString(summary.termination)},
      {"message", summary.message},
      {"iterations", summary.iterations},
      {"samples_used", summary.samples_used},
      {"residual_rms_per_run", per_run},
      {"noise_sigma", NumberOrNull(summary.noise_sigma)},
      {"fit", FitDiagnosticsJson(summary)},
  };
  // Ω taken as exact (estimator/summary.hpp OmegaSensitivity): what 1e-6 rad/s of each such
  // run's Ω does to the estimate, under its own key.
  if (!summary.omega_sensitivity.empty()) {
    nlohmann::json runs = nlohmann::json::array();
    for (const estimator::OmegaSensitivity& o : summary.omega_sensitivity)
      runs.push_back({{"run", o.run_id}, {"delta", Numbers(o.delta)}, {"xi", Numbers(o.xi)}});
    report["omega_sensitivity"] = {{"omega_taken_as_exact", true},
                                   {"step_rad_s", estimator::kOmegaSensitivityStepRadS},
                                   {"runs", runs}};
  }
  const EngineeringOfRecord engineering = ComputeEngineeringOfRecord(summary, record);
  report["engineering"] = EngineeringJson(engineering.quantities, engineering.frequency_source);
  for (const std::string& note : engineering.notes) report["engineering"]["notes"].push_back(note);
  if (nlohmann::json truth = Truth(record.simulation); !truth.is_null()) report["truth"] = truth;
  return report;
}

nlohmann::json FittedRunsJson(const estimator::EstimateSummary& summary) {
  nlohmann::json runs = nlohmann::json::array();
  for (const estimator::RunNuisanceEstimate& n : summary.run_nuisance) {
    nlohmann::json phase = nlohmann::json::array();
    for (const double q : n.phase_coefficients) phase.push_back(NumberOrNull(q));
    runs.push_back({{"run", n.run_id},
                    {"initial_state", Numbers(n.initial_state)},
                    {"phase_coefficients", std::move(phase)},
                    {"omega_offset_rad_s", NumberOrNull(n.omega_offset_rad_s)}});
  }
  return runs;
}

}  // namespace hrgbench::bench
