// The compensation set p from an estimate: every estimated component and its covariance in place,
// a held component kept at its value and flagged (its error is not known: not a zero std), and an
// unusable estimate refused. The prediction of the rate error it leaves: the law of
// docs/estimator/operating-mode.md written out here.

#include "hrgbench/estimator/compensation.hpp"

#include <gtest/gtest.h>

namespace hrgbench::estimator {
namespace {

EstimateSummary EstimateWithHeldComponents() {
  EstimateSummary e;
  e.termination = Termination::kConverged;
  e.delta << -1e-3, 0.29, 3e-5, -2e-5, 2e-4, -1e-4;
  e.delta_estimated = {false, true, true, true, true, true};  // δ1 held
  e.xi << 0.01, 0.0, -0.003, 0.004;
  e.xi_estimated = {true, false, true, true};  // ξ2 held
  // 8 estimated components: δ2…δ6, ξ1, ξ3, ξ4; entry (i, j) = 10·i + j + 1 (symmetrised below).
  e.covariance.resize(8, 8);
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 8; ++j) e.covariance(i, j) = 10.0 * std::min(i, j) + std::max(i, j) + 1.0;
  }
  return e;
}

TEST(CompensationTest, TakesEveryEstimatedComponentWithItsCovarianceAndFlagsTheHeldOnes) {
  CompensationSet p;
  ASSERT_TRUE(CompensationFromEstimate(EstimateWithHeldComponents(), &p));
  EXPECT_EQ(p.delta[0], -1e-3);
  EXPECT_EQ(p.delta[1], 0.29);
  EXPECT_EQ(p.xi[2], -0.003);
  const std::array<bool, 10> estimated = {false, true, true,  true, true,
                                          true,  true, false, true, true};
  EXPECT_EQ(p.estimated, estimated);
  // p's index of each of the summary's 8 components.
  const int where[8] = {1, 2, 3, 4, 5, 6, 8, 9};
  const auto summary = EstimateWithHeldComponents();
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 8; ++j)
      EXPECT_EQ(p.covariance(where[i], where[j]), summary.covariance(i, j));
  }
  EXPECT_EQ(p.covariance.row(0).squaredNorm(), 0.0);
  EXPECT_EQ(p.covariance.col(7).squaredNorm(), 0.0);
}

TEST(CompensationTest, RefusesAnEstimateItCannotUse) {
  CompensationSet p = IdentityCompensation(0.3, -1e-3);
  auto e = EstimateWithHeldComponents();
  e.termination = Termination::kNumericalFailure;
  EXPECT_FALSE(CompensationFromEstimate(e, &p));
  e = EstimateWithHeldComponents();
  e.delta[1] = 0.0;  // no angular gain: no rate can be read
  EXPECT_FALSE(CompensationFromEstimate(e, &p));
  e = EstimateWithHeldComponents();
  e.covariance.resize(7, 7);
  EXPECT_FALSE(CompensationFromEstimate(e, &p));
  EXPECT_EQ(p.delta[1], 0.3);  // left unchanged
  EXPECT_FALSE(CompensationFromEstimate(EstimateWithHeldComponents(), nullptr));
}

TEST(CompensationTest, PredictsTheFirstHarmonicFromTheCovariance) {
  CompensationSet p = IdentityCompensation(0.3, -1e-3);
  // Independent errors: δ3 std 1e-8, δ4 std 2e-8, ξ1 std 1e-6, ξ4 std 3e-6.
  p.covariance(2, 2) = 1e-16;
  p.covariance(3, 3) = 4e-16;
  p.covariance(6, 6) = 1e-12;
  p.covariance(9, 9) = 9e-12;
  const double omega = 0.5;
  const Eigen::Matrix2d cov = PredictedAngleDependentRateErrorCovariance(p, omega);
  // c = −Δδ4/(2δ2) − 2ΩΔξ1, s = Δδ3/(2δ2) − 2ΩΔξ4.
  EXPECT_NEAR(cov(0, 0), 4e-16 / 0.36 + 4.0 * omega * omega * 1e-12, 1e-24);
  EXPECT_NEAR(cov(1, 1), 1e-16 / 0.36 + 4.0 * omega * omega * 9e-12, 1e-24);
  EXPECT_NEAR(cov(0, 1), 0.0, 1e-30);
}

}  // namespace
}  // namespace hrgbench::estimator
