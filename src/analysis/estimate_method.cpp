#include "hrgbench/analysis/estimate_method.hpp"

#include <chrono>

#include "hrgbench/estimator/identifiability.hpp"
#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/paper_method.hpp"

namespace hrgbench::bench {
namespace {

using estimator::XiMask;

std::string XiList(const XiMask& mask) {
  std::string text;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) continue;
    if (!text.empty()) text += ", ";
    text += estimator::kXiNames[i];
  }
  return text.empty() ? "none" : text;
}

}  // namespace

std::optional<Method> ParseMethod(std::string_view name) {
  if (name == "ml") return Method::kMl;
  if (name == "paper") return Method::kPaper;
  if (name == "paper-xi-grid") return Method::kPaperXiGrid;
  return std::nullopt;
}

std::string_view MethodName(Method method) {
  switch (method) {
    case Method::kMl:
      return "ml";
    case Method::kPaper:
      return "paper";
    case Method::kPaperXiGrid:
      return "paper-xi-grid";
  }
  return "?";
}

std::optional<XiMask> ParseXiSet(std::string_view name) {
  if (name == "none") return estimator::kNoXi;
  if (name == "xi1") return estimator::kXi1Only;
  if (name == "all") return estimator::kAllXi;
  return std::nullopt;
}

std::optional<estimator::MlOptions::Covariance> ParseCovariance(std::string_view name) {
  using Covariance = estimator::MlOptions::Covariance;
  if (name == "auto") return Covariance::kAuto;
  if (name == "white") return Covariance::kWhite;
  if (name == "sandwich") return Covariance::kSandwich;
  return std::nullopt;
}

std::size_t MinimumSamples(Method method) {
  if (method == Method::kMl) return static_cast<std::size_t>(estimator::kMlMinimumSamples);
  return static_cast<std::size_t>(estimator::PaperMinimumSamples(estimator::PaperOptions{}));
}

std::string CheckRequest(const MethodRequest& request) {
  if (!request.xi) return {};
  if (request.method == Method::kPaper && *request.xi != estimator::kNoXi) {
    return "--method paper ignores the pick-off errors: only --xi none applies";
  }
  if (request.method == Method::kPaperXiGrid && *request.xi != estimator::kXi1Only) {
    return "--method paper-xi-grid estimates xi1 only: only --xi xi1 applies";
  }
  return {};
}

namespace {

// The paper's methods take every run at once: a set read run by run is copied into memory for them.
std::vector<estimator::RunData> CopyAll(const estimator::RunSet& runs) {
  std::vector<estimator::RunData> out;
  out.reserve(runs.size());
  for (std::size_t r = 0; r < runs.size(); ++r) out.push_back(*runs.Load(r));
  return out;
}

// `all_runs()`: every run in memory, for the paper's methods; `run_set`: the same runs for ml.
template <typename AllRuns>
MethodResult Run(const AllRuns& all_runs, const estimator::RunSet& run_set,
                 const MethodRequest& request) {
  MethodResult result;
  const auto start = std::chrono::steady_clock::now();
  switch (request.method) {
    case Method::kPaper:
      result.summary = estimator::EstimatePaper(all_runs());
      break;
    case Method::kPaperXiGrid:
      result.summary = estimator::EstimatePaperXiGrid(all_runs());
      break;
    case Method::kMl: {
      estimator::MlOptions options;
      options.phase_degree = request.phase_degree;
      options.omega_uncertainty = request.omega_uncertainty;
      options.covariance = request.covariance;
      options.fit_quality = request.fit_quality;
      options.num_threads = request.threads;
      options.noise_shape = request.noise_shape;
      if (request.xi) {
        options.xi_estimated = *request.xi;
      } else {
        std::vector<double> omegas;
        omegas.reserve(run_set.size());
        for (std::size_t r = 0; r < run_set.size(); ++r)
          omegas.push_back(run_set.Info(r).omega_rad_s);
        const estimator::IdentifiabilityReport plan =
            estimator::CheckRatePlan(omegas, estimator::kAllXi, options.identifiability);
        options.xi_estimated = plan.IdentifiableXi(estimator::kAllXi);
        if (options.xi_estimated != estimator::kAllXi) {
          std::string warning =
              options.xi_estimated == estimator::kNoXi
                  ? std::string("the run plan cannot determine any xi: all four held at 0")
                  : "the run plan cannot determine all four xi: estimating " +
                        XiList(options.xi_estimated) + ", the others held at 0";
          for (const std::string& reason : plan.reasons) warning += "; " + reason;
          result.selection_warnings.push_back(warning);
        }
      }
      result.summary = estimator::EstimateMaximumLikelihood(run_set, options);
      break;
    }
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace

MethodResult RunMethod(const std::vector<estimator::RunData>& runs, const MethodRequest& request) {
  return Run([&runs]() -> const std::vector<estimator::RunData>& { return runs; },
             estimator::RunsInMemory(runs), request);
}

MethodResult RunMethod(const estimator::RunSet& runs, const MethodRequest& request) {
  return Run([&runs] { return CopyAll(runs); }, runs, request);
}

}  // namespace hrgbench::bench
