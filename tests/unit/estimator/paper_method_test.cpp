// The paper's estimators on the reference sessions, against the independent prototype's answers
// (expected.json) and MODEL.md's noise-free reproduction.
#include "hrgbench/estimator/paper_method.hpp"

#include <gtest/gtest.h>

#include "reference_data.hpp"

namespace hrgbench::estimator {
namespace {

using hrgbench::testing::DeltaFrom;
using hrgbench::testing::Expected;
using hrgbench::testing::LoadReferenceRuns;

// MODEL.md: without ξ, δ2 ≈ 0.29857 on noise-free data; the prototype's value to ~1e-7 (README).
TEST(PaperMethodTest, NoiseFreeWithoutXiMatchesThePrototype) {
  const EstimateSummary s = EstimatePaper(LoadReferenceRuns("paper-noisefree"));
  ASSERT_TRUE(s.Converged()) << s.message;
  const Delta expected = DeltaFrom(Expected()["paper-noisefree"]["paper_no_xi"]["delta"]);
  EXPECT_NEAR(s.delta[kScaleFactor], 0.29857, 5e-6);
  EXPECT_NEAR(s.delta[kScaleFactor], expected[kScaleFactor], 1e-7);
  for (int j = 0; j < 6; ++j)
    EXPECT_NEAR(s.delta[j], expected[j], 1e-7 * std::abs(expected[kScaleFactor]));
  // The paper's figure of merit: relative deviation ‖δ*−δ0‖/‖δ0‖ = 0.0048 (MODEL.md).
  const Delta truth = (Delta() << -0.001, 0.3, 0, 0, 0, 0).finished();
  EXPECT_NEAR((s.delta - truth).norm() / truth.norm(), 0.0048, 0.0001);
}

TEST(PaperMethodTest, NoisyWithoutXiMatchesThePrototype) {
  const EstimateSummary s = EstimatePaper(LoadReferenceRuns("paper-sigma1e-4"));
  const Delta expected = DeltaFrom(Expected()["paper-sigma1e-4"]["paper_no_xi"]["delta"]);
  EXPECT_NEAR(s.delta[kScaleFactor], expected[kScaleFactor], 1e-7);
}

// MODEL.md: the grid gives ξ1 = 0.01000 and δ2 ≈ 0.30006 (prototype: 0.3000600734).
TEST(PaperMethodTest, XiGridReproducesTheNoiseFreeExperiment) {
  const EstimateSummary s = EstimatePaperXiGrid(LoadReferenceRuns("paper-noisefree"));
  ASSERT_TRUE(s.Converged()) << s.message;
  const nlohmann::json& expected = Expected()["paper-noisefree"]["paper_xi1_grid"];
  EXPECT_NEAR(s.xi[kGainMismatch], 0.01, 0.5e-5);  // within half a grid step
  EXPECT_NEAR(s.xi[kGainMismatch], expected["xi1"].get<double>(), 0.5e-5);
  EXPECT_NEAR(s.delta[kScaleFactor], DeltaFrom(expected["delta"])[kScaleFactor], 1e-7);
  EXPECT_EQ(s.iterations, 10001);  // every grid point of [−0.05, 0.05] at 1e-5
}

TEST(PaperMethodTest, TooShortRunsAreRejected) {
  std::vector<RunData> runs = LoadReferenceRuns("paper-noisefree");
  runs[2].t_s.resize(50);
  runs[2].y.conservativeResize(4, 50);
  const EstimateSummary s = EstimatePaper(runs);
  EXPECT_EQ(s.termination, Termination::kInvalidInput);
  EXPECT_NE(s.message.find("run 3"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("100"), std::string::npos) << s.message;
}

}  // namespace
}  // namespace hrgbench::estimator
