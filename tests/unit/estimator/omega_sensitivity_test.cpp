// Ω taken as exact (no recorded standard error): the estimate says so and gives each parameter's
// sensitivity to a 1e-6 rad/s error of each run's Ω (EstimateSummary::omega_sensitivity), checked
// against an independent finite difference: the whole fit repeated with one run's recorded Ω moved
// by 1e-6 rad/s.
// Provenance: estimator::SimulateRuns (exact propagation, seeded Gaussian noise σ = 1e-4), the
// production design's six rates (±0.1, ±0.3, ±1 rad/s, θ = kπ/12, b = 0, 0.1, 0.2) shortened to
// 20 s at 100 Hz, δ and ξ below, seed 23.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/simulation.hpp"

namespace hrgbench::estimator {
namespace {

std::vector<RunData> Production(double omega_std_rad_s) {
  const double omegas[6] = {0.1, -0.1, 0.3, -0.3, 1.0, -1.0};
  const double bs[6] = {0.0, 0.1, 0.2, 0.0, 0.1, 0.2};
  std::vector<RunPlan> plans;
  for (int r = 0; r < 6; ++r) {
    RunPlan plan;
    plan.omega_rad_s = omegas[r];
    plan.b = bs[r];
    plan.theta_rad = r * std::numbers::pi / 12.0;
    plan.sample_rate_hz = 100.0;
    plan.duration_s = 20.0;
    plans.push_back(plan);
  }
  SimulationOptions sim;
  sim.delta << -1e-3, 0.3, 2e-5, -1e-5, 3e-5, 1e-5;
  sim.xi << 0.004, -0.002, 0.003, 0.001;
  sim.sigma = 1e-4;
  sim.seed = 23;
  std::vector<RunData> runs = SimulateRuns(plans, sim);
  for (RunData& run : runs) run.omega_std_rad_s = omega_std_rad_s;
  return runs;
}

MlOptions Options() {
  MlOptions ml;
  ml.num_threads = 1;
  ml.outlier_threshold_sigma = 0.0;  // the same samples in every fit compared
  return ml;
}

bool AnyContains(const std::vector<std::string>& lines, const std::string& what) {
  for (const std::string& line : lines)
    if (line.find(what) != std::string::npos) return true;
  return false;
}

TEST(OmegaSensitivityTest, OmegaTakenAsExactIsSaidWithSensitivitiesThatMatchARefit) {
  const std::vector<RunData> runs = Production(kNaN);
  const EstimateSummary base = EstimateMaximumLikelihood(runs, Options());
  ASSERT_TRUE(base.Converged()) << base.message;
  EXPECT_TRUE(AnyContains(base.warnings, "Omega taken as exact in runs 1, 2, 3, 4, 5, 6"));
  ASSERT_EQ(base.omega_sensitivity.size(), 6u);
  // The finite difference re-fits from scratch; its own convergence error (steps below 1e-6 std)
  // and the linearisation's (O(ε²), ε = 1e-6 rad/s against rates ≥ 0.1) are far below the
  // tolerance: 1 % of the parameter's std plus 1 % of the change.
  double largest_in_std = 0.0;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    SCOPED_TRACE("run " + std::to_string(r + 1));
    EXPECT_EQ(base.omega_sensitivity[r].run_id, runs[r].id);
    std::vector<RunData> moved = runs;
    moved[r].omega_rad_s += kOmegaSensitivityStepRadS;
    const EstimateSummary refit = EstimateMaximumLikelihood(moved, Options());
    ASSERT_TRUE(refit.Converged()) << refit.message;
    for (int j = 0; j < 6; ++j) {
      const double fd = refit.delta[j] - base.delta[j];
      EXPECT_NEAR(base.omega_sensitivity[r].delta[j], fd,
                  0.01 * base.delta_std[j] + 0.01 * std::abs(fd))
          << "delta" << j + 1;
      largest_in_std = std::max(largest_in_std, std::abs(fd) / base.delta_std[j]);
    }
    for (int k = 0; k < 4; ++k) {
      const double fd = refit.xi[k] - base.xi[k];
      EXPECT_NEAR(base.omega_sensitivity[r].xi[k], fd, 0.01 * base.xi_std[k] + 0.01 * std::abs(fd))
          << "xi" << k + 1;
      largest_in_std = std::max(largest_in_std, std::abs(fd) / base.xi_std[k]);
    }
  }
  // Not a vacuous comparison: a 1e-6 rad/s error moves some parameter by a sizeable part of its
  // std (the 3e-6 rad/s moved δ2 by about 1.8 std).
  EXPECT_GT(largest_in_std, 0.3);
}

TEST(OmegaSensitivityTest, RecordedOmegaUncertaintyNeedsNoSensitivity) {
  // Every Ω with its recorded std enters the fit (and its std): nothing taken as exact, nothing
  // said. Turned off (hrg-estimate --omega-exact), it is said again.
  const std::vector<RunData> runs = Production(1e-6);
  const EstimateSummary s = EstimateMaximumLikelihood(runs, Options());
  ASSERT_TRUE(s.Converged()) << s.message;
  EXPECT_TRUE(s.omega_sensitivity.empty());
  EXPECT_FALSE(AnyContains(s.warnings, "Omega taken as exact"));
  MlOptions exact = Options();
  exact.omega_uncertainty = false;
  const EstimateSummary e = EstimateMaximumLikelihood(runs, exact);
  EXPECT_EQ(e.omega_sensitivity.size(), 6u);
  EXPECT_TRUE(AnyContains(e.warnings, "Omega taken as exact"));
}

}  // namespace
}  // namespace hrgbench::estimator
