// The output-error problem's shortcuts (src/estimator/output_error_problem.hpp), each against the
// full computation it stands for:
//  - InformationAt: the information of a problem with Ω as one more nuisance, from the Gram sums of
//    a linearisation without it, against a linearisation of that problem over the data;
//  - SolveInitialStates from a thinned run: on noise-free data the same w0 as from every sample;
//    under noise within the thinned solve's own noise of it;
//  - the integral-equation start from block-averaged equations (StartMonomialSums): within 1e-3
//    of the start's own error of the start from every equation.
// Provenance: estimator::SimulateRuns (exact propagation, seeded Gaussian noise), the production
// design's six rates (±0.1, ±0.3, ±1 rad/s, θ = kπ/12, b = 0, 0.1, 0.2) at 1 kHz, δ and ξ below.
#include "estimator/output_error_problem.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "estimator/integral_equation_error.hpp"
#include "hrgbench/estimator/simulation.hpp"

namespace hrgbench::estimator::internal {
namespace {

SimulationOptions Truth(double sigma) {
  SimulationOptions sim;
  sim.delta << -1e-3, 0.3, 2e-6, -1e-6, 3e-5, -2e-5;
  sim.xi << 0.01, -0.003, 0.002, 0.004;
  sim.sigma = sigma;
  sim.seed = 31;
  return sim;
}

std::vector<RunData> Production(double duration_s, double sigma) {
  const double omegas[6] = {0.1, -0.1, 0.3, -0.3, 1.0, -1.0};
  std::vector<RunPlan> plans;
  for (int r = 0; r < 6; ++r) {
    RunPlan plan;
    plan.omega_rad_s = omegas[r];
    plan.b = 0.1 * (r % 3);
    plan.theta_rad = r * std::numbers::pi / 12.0;
    plan.sample_rate_hz = 1000.0;
    plan.duration_s = duration_s;
    plans.push_back(plan);
  }
  return SimulateRuns(plans, Truth(sigma));
}

std::vector<int> EveryParameter() { return {0, 1, 2, 3, 4, 5, 6, 7, 8, 9}; }

TEST(OutputErrorProblemTest, InformationFromTheGramSumsEqualsALinearisationWithTheSameColumns) {
  const std::vector<RunData> data = Production(5.0, 1e-4);
  const RunsInMemory runs(data);
  const SimulationOptions truth = Truth(1e-4);
  const FullParameters p = Pack(truth.delta, truth.xi);
  NuisanceModel model;
  model.phase_degree = 2;
  const OutputErrorProblem problem(runs, EveryParameter(), 1, 0, model);
  std::vector<RunNuisance> nuisance;
  ASSERT_TRUE(problem.SolveInitialStates(p, &nuisance));
  for (RunNuisance& n : nuisance) {
    n[NuisanceModel::PhaseIndex(1)] = 2e-3;  // a common phase, so its columns are not trivial
    n[NuisanceModel::PhaseIndex(2)] = -1e-5;
  }
  NormalEquations base;
  problem.Linearize(p, nuisance, &base);

  // Ω as one more nuisance of every run (ΔΩ = 0 there).
  NuisanceModel with_omega = model;
  with_omega.omega_prior_weight.assign(runs.size(), 1.0);
  std::vector<RunNuisance> extended = nuisance;
  for (RunNuisance& n : extended) {
    n.conservativeResize(n.size() + 1);
    n[n.size() - 1] = 0.0;
  }
  const OutputErrorProblem omega_problem(runs, EveryParameter(), 1, 0, with_omega);
  NormalEquations direct, from_gram;
  omega_problem.Linearize(p, extended, &direct);
  ASSERT_TRUE(omega_problem.InformationAt(base, extended, &from_gram));

  const auto close = [](const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    ASSERT_EQ(a.rows(), b.rows());
    ASSERT_EQ(a.cols(), b.cols());
    // Every entry within 1e-9 of the block's largest: the same sums in another order.
    EXPECT_LE((a - b).cwiseAbs().maxCoeff(), 1e-9 * b.cwiseAbs().maxCoeff());
  };
  close(from_gram.h_pp, direct.h_pp);
  for (std::size_t r = 0; r < runs.size(); ++r) {
    close(from_gram.h_px[r], direct.h_px[r]);
    close(from_gram.h_xx[r], direct.h_xx[r]);
  }
  // The ΔΩ column is really there, not zero.
  EXPECT_GT(direct.h_xx[0](with_omega.OmegaIndex(), with_omega.OmegaIndex()), 0.0);

  // Sums of another common phase's basis are refused, not misread.
  NuisanceModel other = model;
  other.phase_degree = 1;
  std::vector<RunNuisance> shorter = nuisance;
  for (RunNuisance& n : shorter) n.conservativeResize(other.Size(0));
  const OutputErrorProblem other_problem(runs, EveryParameter(), 1, 0, other);
  NormalEquations refused;
  EXPECT_FALSE(other_problem.InformationAt(base, shorter, &refused));
}

TEST(OutputErrorProblemTest, InitialStatesFromAThinnedRunAreTheFullRunsWithinTheirNoise) {
  const SimulationOptions truth = Truth(0.0);
  const FullParameters p = Pack(truth.delta, truth.xi);
  const Eigen::Index thinned = 1000;  // 20 000 samples per run: every 20th
  {
    // Noise-free: both solves are exact.
    const std::vector<RunData> data = Production(20.0, 0.0);
    const RunsInMemory runs(data);
    const OutputErrorProblem problem(runs, {}, 1, 0, {});
    std::vector<RunNuisance> full, thin;
    ASSERT_TRUE(problem.SolveInitialStates(p, &full));
    ASSERT_TRUE(problem.SolveInitialStates(p, &thin, nullptr, thinned));
    for (std::size_t r = 0; r < runs.size(); ++r)
      EXPECT_LE((thin[r] - full[r]).cwiseAbs().maxCoeff(), 1e-10) << "run " << r;
  }
  {
    // σ = 1e-4: each w0 entry from ~1000 samples has a std of about σ/√1000 ≈ 3e-6 (the signal's
    // amplitude is ~1); the full solve's is ~4.5 times smaller.
    const double sigma = 1e-4;
    const std::vector<RunData> data = Production(20.0, sigma);
    const RunsInMemory runs(data);
    const OutputErrorProblem problem(runs, {}, 1, 0, {});
    std::vector<RunNuisance> full, thin;
    InitialStatesCost full_cost, thin_cost;
    ASSERT_TRUE(problem.SolveInitialStates(p, &full, &full_cost));
    ASSERT_TRUE(problem.SolveInitialStates(p, &thin, &thin_cost, thinned));
    double largest = 0.0;
    for (std::size_t r = 0; r < runs.size(); ++r)
      largest = std::max(largest, (thin[r] - full[r]).cwiseAbs().maxCoeff());
    EXPECT_LE(largest, 6.0 * sigma / std::sqrt(static_cast<double>(thinned)));
    EXPECT_GT(largest, 0.0);  // it did thin
    // The cost is over the samples used: σ² per observation there.
    const double observations = 4.0 * static_cast<double>(thinned) * 6.0;
    EXPECT_NEAR(thin_cost.cost / observations, sigma * sigma, 0.05 * sigma * sigma);
  }
}

TEST(OutputErrorProblemTest, BlockAveragedStartEquationsGiveTheStartOfEveryEquation) {
  // At 1 kHz the start's equations are averaged over 8 samples; at 100 Hz they are not (a block is
  // at most 8 ms). The same runs sampled at 1 kHz and, for the reference, every equation: the
  // monomial sums of 1 kHz data thinned to 100 Hz use every one of theirs.
  const std::vector<RunData> data = Production(20.0, 1e-4);
  const RunsInMemory runs(data);
  const SimulationOptions truth = Truth(1e-4);
  const std::array<bool, 6> all_delta = {true, true, true, true, true, true};
  const XiMask all_xi = {true, true, true, true};
  IntegralEquationResult blocked;
  blocked.initial_forms_free = true;
  ASSERT_TRUE(IntegralEquationError(runs, all_delta, Delta::Zero(), all_xi, Xi::Zero(), &blocked));
  // Every equation: the block is chosen from the mean step, so a run whose time stamps are scaled
  // by 100 (a step of 0.1 s) is averaged over no block. Time scaled by c and Ω by 1/c is the same
  // motion with δ1, δ3…δ6 scaled by 1/c (δ2 enters as Ω·δ2, ξ not at all).
  std::vector<RunData> slow = data;
  for (RunData& run : slow) {
    for (double& t : run.t_s) t *= 100.0;
    run.omega_rad_s /= 100.0;
  }
  const RunsInMemory slow_runs(slow);
  IntegralEquationResult every;
  every.initial_forms_free = true;
  ASSERT_TRUE(
      IntegralEquationError(slow_runs, all_delta, Delta::Zero(), all_xi, Xi::Zero(), &every));
  for (int j = 0; j < 6; ++j) {
    const double every_delta = every.delta[j] * (j == kScaleFactor ? 1.0 : 100.0);
    const double start_error = std::abs(every_delta - truth.delta[j]);
    // Within a tenth of the start's own error, or 1e-9 absolute where that is smaller than
    // rounding.
    EXPECT_LE(std::abs(blocked.delta[j] - every_delta), std::max(0.1 * start_error, 1e-9))
        << "delta" << j + 1;
  }
  for (int k = 0; k < 4; ++k) {
    const double start_error = std::abs(every.xi[k] - truth.xi[k]);
    EXPECT_LE(std::abs(blocked.xi[k] - every.xi[k]), 1e-3 * start_error) << "xi" << k + 1;
  }
}

}  // namespace
}  // namespace hrgbench::estimator::internal
