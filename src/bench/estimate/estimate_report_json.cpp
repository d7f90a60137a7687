#include "hrgbench/bench/estimate_report_json.hpp"

#include <cmath>

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

nlohmann::json Truth(const nlohmann::json& document) {
  if (!document.is_object() || !document.contains("simulation")) return nullptr;
  const nlohmann::json& simulation = document["simulation"];
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

nlohmann::json EstimateReportJson(std::string_view method,
                                  const estimator::EstimateSummary& summary,
                                  const std::vector<std::string>& warnings,
                                  const nlohmann::json& session_document) {
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
  };
  if (nlohmann::json truth = Truth(session_document); !truth.is_null()) report["truth"] = truth;
  return report;
}

}  // namespace hrgbench::bench
