#pragma once
// Choosing and running an estimator for a session: the policy shared by hrg-estimate and
// hrg-compare, so both answer the same question the same way.
//
// Default ξ set for maximum likelihood: all four when the plan's rates make them identifiable
// (CheckRatePlan), else the largest identifiable subset, said in a warning. An explicit request is
// passed through unchanged: the estimator's kFix policy then holds what the plan cannot determine,
// and warns.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/noise_shape.hpp"
#include "hrgbench/estimator/parameters.hpp"
#include "hrgbench/estimator/run_data.hpp"
#include "hrgbench/estimator/run_set.hpp"
#include "hrgbench/estimator/summary.hpp"

namespace hrgbench::bench {

enum class Method { kMl, kPaper, kPaperXiGrid };

std::optional<Method> ParseMethod(std::string_view name);  // "ml", "paper", "paper-xi-grid"
std::string_view MethodName(Method method);

// "none", "xi1", "all".
std::optional<estimator::XiMask> ParseXiSet(std::string_view name);

// Samples per run the method needs (the session reader's min_samples_per_run).
std::size_t MinimumSamples(Method method);

struct MethodRequest {
  Method method = Method::kMl;
  // The ξ to estimate; nullopt = the method's default (ML: the identifiable set; paper: none;
  // paper-xi-grid: ξ1). The paper methods accept only their own set.
  std::optional<estimator::XiMask> xi;
  // ML only: the per-run common phase degree (MlOptions::phase_degree), whether recorded Ω
  // uncertainties enter the fit, which covariance, and the fit-quality thresholds.
  int phase_degree = estimator::MlOptions{}.phase_degree;
  bool omega_uncertainty = true;
  estimator::MlOptions::Covariance covariance = estimator::MlOptions::Covariance::kAuto;
  estimator::FitQualityLimits fit_quality;
  // ML only: the pick-off noise's shape the session's record declares (RecordedNoiseShape in
  // output_filter.hpp); white by default.
  estimator::NoiseShape noise_shape;
  // ML only: the estimator's threads (MlOptions::num_threads; 0: the hardware's). The answer is
  // the same for any count.
  int threads = 0;
};

// "auto", "white", "sandwich".
std::optional<estimator::MlOptions::Covariance> ParseCovariance(std::string_view name);

// Empty when the request is consistent; else a one-line reason (bad input).
std::string CheckRequest(const MethodRequest& request);

struct MethodResult {
  estimator::EstimateSummary summary;
  // Warnings of the selection itself (before the estimator's own, which are in summary.warnings).
  std::vector<std::string> selection_warnings;
  double seconds = 0.0;  // wall time of the estimator call
};

// Runs the requested method on `runs` (CheckRequest must have passed).
MethodResult RunMethod(const std::vector<estimator::RunData>& runs, const MethodRequest& request);
// The same on runs read run by run (estimator/run_set.hpp): ml keeps to the set's memory; the
// paper's methods copy every run into memory first.
MethodResult RunMethod(const estimator::RunSet& runs, const MethodRequest& request);

}  // namespace hrgbench::bench
