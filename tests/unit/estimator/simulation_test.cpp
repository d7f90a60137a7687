// The closed-form simulation against Eigen's general matrix exponential (Padé with scaling and
// squaring: an independent algorithm), and the noise generator's statistics.
#include "hrgbench/estimator/simulation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <unsupported/Eigen/MatrixFunctions>

namespace hrgbench::estimator {
namespace {

TEST(SimulationTest, ClosedFormMatchesMatrixExponential) {
  const Delta d = (Delta() << -1e-3, 0.3, 2e-4, -1e-4, 3e-4, 1e-4).finished();
  const State x0 = OrbitToState(Orbit{1.0, 0.3, 0.4, 0.1});
  for (double omega : {0.0, 1e-4, 0.3, -1.0}) {
    for (double t : {0.0, 1e-3, 0.5, 10.0, 100.0}) {
      const Matrix4 a_t = SystemMatrix(omega, d) * t;
      const State expected = a_t.exp() * x0;
      EXPECT_LT((PropagateExact(omega, d, x0, t) - expected).norm(), 1e-12 * (1.0 + t))
          << "omega " << omega << " t " << t;
    }
  }
}

// μ = 0 exactly (no anisotropy, Ω = 0): the series branch must give the pure decay.
TEST(SimulationTest, DegenerateSpectrumIsPureDecay) {
  const Delta d = (Delta() << -2e-3, 0.3, 0, 0, 0, 0).finished();
  const State x0 = OrbitToState(Orbit{1.0, -0.2, 0.3, 0.0});
  EXPECT_LT((PropagateExact(0.0, d, x0, 7.0) - std::exp(-2e-3 * 7.0) * x0).norm(), 1e-15);
}

TEST(SimulationTest, RunsHaveThePlannedTimeBase) {
  RunPlan plan;
  plan.sample_rate_hz = 100.0;
  plan.duration_s = 10.0;
  const std::vector<RunData> runs = SimulateRuns({plan, plan}, SimulationOptions{});
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0].size(), 1000);  // t = 0 … 9.99 s, as in the reference data
  EXPECT_DOUBLE_EQ(runs[0].t_s.back(), 9.99);
  EXPECT_EQ(runs[1].id, 2);
}

TEST(SimulationTest, DistortionAndInitialStateAreApplied) {
  RunPlan plan;
  plan.a = 1.0;
  plan.b = -0.4;
  SimulationOptions options;
  options.delta << -1e-3, 0.3, 0, 0, 0, 0;
  options.xi << 0.01, 0, 0, 0;
  const std::vector<RunData> runs = SimulateRuns({plan}, options);
  // The paper's first sample (reference data, run 1): y = (1.01, 0, 0, −0.396).
  EXPECT_NEAR(runs[0].y(0, 0), 1.01, 1e-15);
  EXPECT_NEAR(runs[0].y(3, 0), -0.396, 1e-15);
}

TEST(SimulationTest, NoiseHasTheRequestedStatisticsAndIsReproducible) {
  RunPlan plan;
  plan.sample_rate_hz = 1000.0;
  plan.duration_s = 50.0;
  SimulationOptions clean, noisy;
  noisy.sigma = 1e-3;
  noisy.seed = 42;
  const std::vector<RunData> a = SimulateRuns({plan}, clean);
  const std::vector<RunData> b = SimulateRuns({plan}, noisy);
  const Eigen::Matrix4Xd noise = b[0].y - a[0].y;
  const double n = static_cast<double>(noise.size());
  const double mean = noise.sum() / n;
  const double std_dev = std::sqrt((noise.array() - mean).square().sum() / (n - 1));
  // 200 000 draws: the mean's std is 2.2e-6, the sample std's relative std 0.16 %; 5 sigma bounds.
  EXPECT_NEAR(mean, 0.0, 1.2e-5);
  EXPECT_NEAR(std_dev, 1e-3, 1e-3 * 0.008);
  EXPECT_EQ(SimulateRuns({plan}, noisy)[0].y, b[0].y);
  noisy.seed = 43;
  EXPECT_NE(SimulateRuns({plan}, noisy)[0].y, b[0].y);
}

TEST(SimulationTest, InvalidInputIsRejectedWithAReason) {
  RunPlan bad;
  bad.sample_rate_hz = -1.0;
  std::string why;
  EXPECT_TRUE(SimulateRuns({bad}, SimulationOptions{}, &why).empty());
  EXPECT_NE(why.find("sample_rate_hz"), std::string::npos);
  SimulationOptions options;
  options.sigma = -1.0;
  EXPECT_TRUE(SimulateRuns({RunPlan{}}, options, &why).empty());
  EXPECT_NE(why.find("sigma"), std::string::npos);
}

}  // namespace
}  // namespace hrgbench::estimator
