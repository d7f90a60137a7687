// FittedOutput / FittedState: the fitted model of a run, as a report draws it.
//
// Data: the production design (tests/support/out_of_model.hpp: six runs at ±0.1, ±0.3, ±1 rad/s,
// ProductionTruth's δ and all four ξ), simulated by SimulateRuns (closed-form exp(A·t), seeded
// noise). The independent derivations: noise-free data are the model itself, so ŷ must equal y;
// with noise, the fit's own residual RMS (summary.residual_rms_per_run, accumulated inside the
// estimator's sample loop) must equal the RMS of y − ŷ computed here.
#include "hrgbench/estimator/fitted_output.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/model.hpp"
#include "hrgbench/estimator/simulation.hpp"
#include "out_of_model.hpp"

namespace hrgbench::estimator {
namespace {

using testing::AddNoise;
using testing::ApplyFrequencyRamp;
using testing::ProductionPlans;
using testing::ProductionTruth;

double Rms(const Eigen::Matrix4Xd& y, const RunChannels& fitted) {
  return std::sqrt((y.transpose() - fitted).squaredNorm() / (4.0 * static_cast<double>(y.cols())));
}

TEST(FittedOutput, ReproducesNoiseFreeDataToRounding) {
  SimulationOptions truth = ProductionTruth();
  const std::vector<RunData> runs = SimulateRuns(ProductionPlans(4.0, 250.0), truth);
  ASSERT_EQ(runs.size(), 6u);
  const EstimateSummary summary = EstimateMaximumLikelihood(runs);
  ASSERT_TRUE(summary.IsUsable()) << summary.message;
  ASSERT_EQ(summary.run_nuisance.size(), runs.size());
  for (const RunData& run : runs) {
    const RunChannels fitted = FittedOutput(summary, run);
    ASSERT_EQ(fitted.rows(), run.size());
    const double scale = run.y.cwiseAbs().maxCoeff();
    EXPECT_LT((run.y.transpose() - fitted).cwiseAbs().maxCoeff(), 1e-9 * scale) << "run " << run.id;
    // The state before the distortion: (I + C(ξ))·x̂ = ŷ, and x̂(0) = the summary's x(0).
    const RunChannels state = FittedState(summary, run);
    const Eigen::Matrix4d distortion = Eigen::Matrix4d::Identity() + DistortionMatrix(summary.xi);
    const Eigen::MatrixXd again = (distortion * state.transpose()).transpose();
    EXPECT_LT((again - fitted).cwiseAbs().maxCoeff(), 1e-12 * scale);
    const std::size_t r = static_cast<std::size_t>(&run - runs.data());
    EXPECT_LT((state.row(0).transpose() - summary.initial_states[r]).norm(), 1e-12 * scale);
  }
}

// With noise, a frequency ramp (so the common phase q1, q2 are non-zero) and a recorded Ω
// uncertainty (so ΔΩ is fitted): every nuisance the fit has enters the residual.
TEST(FittedOutput, ResidualRmsIsTheFitsOwn) {
  SimulationOptions truth = ProductionTruth();
  std::vector<RunData> runs = SimulateRuns(ProductionPlans(4.0, 250.0), truth);
  ASSERT_EQ(runs.size(), 6u);
  for (std::size_t r = 0; r < runs.size(); ++r) {
    ApplyFrequencyRamp(&runs[r], 2e-3 * (1.0 + static_cast<double>(r)));
    AddNoise(&runs[r], 1e-4, 0.0, 4242 + r);
    runs[r].omega_std_rad_s = 1e-5;
  }
  const EstimateSummary summary = EstimateMaximumLikelihood(runs);
  ASSERT_TRUE(summary.IsUsable()) << summary.message;
  ASSERT_EQ(summary.residual_rms_per_run.size(), runs.size());
  bool omega_offset_seen = false;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    ASSERT_EQ(summary.diagnostics.runs[r].outliers_removed, 0u);
    const RunNuisanceEstimate& n = summary.run_nuisance[r];
    EXPECT_EQ(n.run_id, runs[r].id);
    ASSERT_EQ(n.phase_coefficients.size(), 2u);  // the default phase degree
    EXPECT_GT(std::abs(n.phase_coefficients[1]), 1e-5);  // the ramp is seen
    omega_offset_seen = omega_offset_seen || n.omega_offset_rad_s != 0.0;
    const double rms = Rms(runs[r].y, FittedOutput(summary, runs[r]));
    EXPECT_NEAR(rms, summary.residual_rms_per_run[r], 1e-9 * summary.residual_rms_per_run[r])
        << "run " << runs[r].id;
    // The fit is at noise level: the model is right, the residual is the noise.
    EXPECT_NEAR(rms, 1e-4, 0.1e-4);
  }
  EXPECT_TRUE(omega_offset_seen);
}

TEST(FittedOutput, UnknownRunOrNoNuisanceGivesEmpty) {
  SimulationOptions truth = ProductionTruth();
  std::vector<RunData> runs = SimulateRuns(ProductionPlans(2.0, 100.0), truth);
  const EstimateSummary summary = EstimateMaximumLikelihood(runs);
  ASSERT_TRUE(summary.IsUsable());
  RunData other = runs[0];
  other.id = 99;
  EXPECT_EQ(FittedOutput(summary, other).rows(), 0);
  EXPECT_EQ(FittedState(summary, other).rows(), 0);
  EXPECT_EQ(FittedOutput(EstimateSummary{}, runs[0]).rows(), 0);
}

}  // namespace
}  // namespace hrgbench::estimator
