#include "hrgbench/analysis/next_run.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "hrgbench/analysis/engineering_of_record.hpp"
#include "hrgbench/estimator/cramer_rao.hpp"

namespace hrgbench::bench {
namespace {

// The bound's sample rate: the demodulated channels' content is below 1 Hz (decay, Ω up to a few
// rad/s), so 20 samples/s carry the same information as 1000 at σ·√(20/1000).
constexpr double kBoundSampleRateHz = 20.0;

// The statistical u of every limited quantity under `covariance` (δ then the estimated ξ, as
// EstimateSummary::covariance), NaN where it has none.
std::vector<double> LimitStds(const estimator::EstimateSummary& estimate,
                              const session::SessionRecord& record,
                              const Eigen::MatrixXd& covariance,
                              std::span<const LimitResult> limits) {
  estimator::EstimateSummary with = estimate;
  with.covariance = covariance;
  Eigen::Index index = 0;
  for (int j = 0; j < 6; ++j, ++index) with.delta_std[j] = std::sqrt(covariance(index, index));
  for (int k = 0; k < 4; ++k) {
    if (!estimate.xi_estimated[static_cast<std::size_t>(k)]) continue;
    with.xi_std[k] = std::sqrt(covariance(index, index));
    ++index;
  }
  const estimator::EngineeringQuantities quantities =
      ComputeEngineeringOfRecord(with, record).quantities;
  std::vector<double> out;
  for (const LimitResult& limit : limits) {
    const auto q = static_cast<std::size_t>(limit.quantity);
    double u = estimator::kNaN;
    if (q < 6) {
      u = with.delta_std[static_cast<Eigen::Index>(q)];
    } else if (q < 10) {
      u = with.xi_std[static_cast<Eigen::Index>(q - 6)];
    } else if (const auto e = EngineeringOf(limit.quantity)) {
      u = quantities[*e].statistical_std;
    }
    out.push_back(u);
  }
  return out;
}

std::optional<Eigen::MatrixXd> Bound(const estimator::EstimateSummary& estimate,
                                     std::vector<estimator::RunPlan> runs) {
  estimator::DesignSpec design;
  design.delta = estimate.delta;
  design.xi = estimate.xi;
  design.xi_unknown = estimate.xi_estimated;
  double rate_hz = 0.0;
  for (const estimator::RunPlan& run : runs) rate_hz = std::max(rate_hz, run.sample_rate_hz);
  const double bound_rate_hz = std::min(rate_hz, kBoundSampleRateHz);
  design.sigma = estimate.noise_sigma * std::sqrt(bound_rate_hz / rate_hz);
  for (estimator::RunPlan& run : runs)
    run.sample_rate_hz = std::min(run.sample_rate_hz, bound_rate_hz);
  design.runs = std::move(runs);
  std::string why;
  if (!design.IsValid(&why)) return std::nullopt;
  estimator::CrlbResult bound = estimator::CramerRaoBound(design);
  if (!bound.valid || !bound.covariance.allFinite()) return std::nullopt;
  return std::move(bound.covariance);
}

}  // namespace

std::vector<double> NextRunScores(const estimator::EstimateSummary& estimate,
                                  const Verdict& verdict, const session::SessionRecord& record,
                                  std::span<const estimator::RunPlan> made,
                                  std::span<const NextRunCandidate> candidates) {
  std::vector<LimitResult> undecided;
  for (const LimitResult& r : verdict.results)
    if (r.zone == DecisionZone::kUndecided) undecided.push_back(r);
  if (undecided.empty() || candidates.empty() || made.empty() || !estimate.IsUsable() ||
      !(estimate.noise_sigma > 0.0) || !estimate.delta.allFinite())
    return {};
  for (const bool estimated : estimate.delta_estimated)
    if (!estimated) return {};  // the bound takes every δ as unknown

  const std::vector<estimator::RunPlan> so_far(made.begin(), made.end());
  const std::optional<Eigen::MatrixXd> now = Bound(estimate, so_far);
  if (!now) return {};
  const std::vector<double> u_now = LimitStds(estimate, record, *now, undecided);
  std::vector<double> scores;
  for (const NextRunCandidate& candidate : candidates) {
    std::vector<estimator::RunPlan> with = so_far;
    with.push_back(candidate.plan);
    const std::optional<Eigen::MatrixXd> bound = Bound(estimate, std::move(with));
    if (!bound) return {};
    const std::vector<double> u_with = LimitStds(estimate, record, *bound, undecided);
    double gain = 0.0;
    for (std::size_t l = 0; l < undecided.size(); ++l) {
      if (std::isfinite(u_now[l]) && std::isfinite(u_with[l]) && u_with[l] > 0.0)
        gain += std::max(0.0, u_now[l] * u_now[l] / (u_with[l] * u_with[l]) - 1.0);
    }
    scores.push_back(gain / std::max(candidate.table_s, 1e-3));
  }
  return scores;
}

}  // namespace hrgbench::bench
