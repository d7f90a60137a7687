// The compensation set p from an estimate: every estimated component and its covariance in place,
// a held component kept at its value and flagged (its error is not known: not a zero std), and an
// unusable estimate refused. The prediction of the rate error it leaves: the law of
// docs/estimator/operating-mode.md written out here.

#include "hrgbench/estimator/compensation.hpp"

#include <gtest/gtest.h>

#include <vector>

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
  const std::array<bool, 11> estimated = {false, true,  true, true, true, true,
                                          true,  false, true, true, false};
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
  EXPECT_EQ(p.covariance.col(kCompensationBias).squaredNorm(), 0.0);  // free runs see no bias
  EXPECT_EQ(p.rate_bias_rad_s, 0.0);
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

TEST(CompensationTest, PredictsTheBiasAndFirstHarmonicFromTheCovariance) {
  CompensationSet p = IdentityCompensation(0.3, -1e-3);
  // Independent errors: δ3 std 1e-8, δ4 std 2e-8, ξ1 std 1e-6, ξ4 std 3e-6.
  p.covariance(2, 2) = 1e-16;
  p.covariance(3, 3) = 4e-16;
  p.covariance(6, 6) = 1e-12;
  p.covariance(9, 9) = 9e-12;
  const double omega = 0.5;
  p.covariance(1, 1) = 1e-18;  // δ2 std 1e-9
  const Eigen::Matrix3d cov = PredictedRateErrorCovariance(p, omega);
  // b = (δ2/δ̂2 − 1)Ω − Δb̂, c = −Δδ4/(2δ2) − 2ΩΔξ1, s = Δδ3/(2δ2) − 2ΩΔξ4.
  EXPECT_NEAR(cov(0, 0), omega * omega / 0.09 * 1e-18, 1e-30);
  EXPECT_NEAR(cov(1, 1), 4e-16 / 0.36 + 4.0 * omega * omega * 1e-12, 1e-24);
  EXPECT_NEAR(cov(2, 2), 1e-16 / 0.36 + 4.0 * omega * omega * 9e-12, 1e-24);
  EXPECT_NEAR(cov(1, 2), 0.0, 1e-30);
  p.covariance(kCompensationBias, kCompensationBias) = 4e-18;
  EXPECT_NEAR(PredictedRateErrorCovariance(p, omega)(0, 0), omega * omega / 0.09 * 1e-18 + 4e-18,
              1e-30);
}

// Holds made from a known operating mode: c = c0 + c1·Ω, s = s0 + s1·Ω, b = b0 + b1·Ω exactly,
// with c0 = −Δδ4/(2δ2), s0 = Δδ3/(2δ2), c1 = −2Δξ1, s1 = −2Δξ4, b1 = δ2/δ̂2 − 1 (operating-mode.md).
TEST(CompensationTest, RefinesTheDriftAndBiasFromHoldsAtTwoRatesAndChecksTheSlopes) {
  CompensationSet p = IdentityCompensation(0.3, -1e-3);
  p.delta[2] = 1e-5;
  p.delta[3] = -1e-5;
  p.rate_bias_rad_s = 1e-7;
  p.covariance(2, 2) = p.covariance(3, 3) = 1e-18;
  p.covariance(2, 6) = p.covariance(6, 2) = 1e-19;  // δ3 correlated with ξ1 in the free runs
  const double d_delta3 = 2e-6, d_delta4 = -3e-6, d_xi1 = 1e-6, d_xi4 = -2e-6, scale = 5e-7,
               bias = 4e-7;
  std::vector<VerificationHold> holds;
  for (const double omega : {0.3, -0.3, 1.0}) {
    VerificationHold h;
    h.omega_rad_s = omega;
    h.cos_rad_s = -d_delta4 / 0.6 - 2.0 * omega * d_xi1;
    h.sin_rad_s = d_delta3 / 0.6 - 2.0 * omega * d_xi4;
    h.bias_rad_s = bias + scale * omega;
    h.cos_std_rad_s = h.sin_std_rad_s = 1e-8;
    h.bias_std_rad_s = 2e-9;
    holds.push_back(h);
  }
  CompensationRefinement r;
  ASSERT_TRUE(RefineCompensation(p, holds, &r));
  EXPECT_NEAR(r.refined.delta[2], 1e-5 + d_delta3, 1e-15);
  EXPECT_NEAR(r.refined.delta[3], -1e-5 + d_delta4, 1e-15);
  EXPECT_NEAR(r.refined.rate_bias_rad_s, 1e-7 + bias, 1e-18);
  EXPECT_NEAR(r.slope_check[0], d_xi1, 1e-15);
  EXPECT_NEAR(r.slope_check[1], d_xi4, 1e-15);
  EXPECT_NEAR(r.slope_check[2], scale, 1e-18);
  // The refined entries' std are the intercepts' (weighted LS over Ω = 0.3, −0.3, 1 with equal σ:
  // var(a) = σ²·ΣΩ²/(n·ΣΩ² − (ΣΩ)²) = σ²·1.18/(3·1.18 − 1)), times 2δ2 for δ3, δ4.
  const double var_intercept = 1.18 / (3.0 * 1.18 - 1.0);
  EXPECT_NEAR(r.refined.covariance(2, 2), 0.36 * 1e-16 * var_intercept, 1e-24);
  EXPECT_NEAR(r.refined.covariance(10, 10), 4e-18 * var_intercept, 1e-26);
  EXPECT_EQ(r.refined.covariance(2, 6), 0.0);  // the table's data, not the free runs'
  EXPECT_TRUE(r.refined.estimated[10]);
  EXPECT_EQ(r.refined.xi, p.xi);  // ξ and δ2 held exactly by p (zero variance): not moved
  EXPECT_EQ(r.refined.delta[1], p.delta[1]);

  // With ξ1 known as well by p as by the slope, the two are averaged and the variance halved; an
  // entry correlated with ξ1 follows (δ1 here, with a correlation of 0.5).
  CompensationSet q = p;
  const double slope_std = 0.5 * std::sqrt(1e-16 * 1.0 / (3.0 * 1.18 - 1.0) * 3.0);
  // (the slope's variance: σ²·n/(n·ΣΩ² − (ΣΩ)²) for c, halved for Δξ1 = −c1/2)
  q.covariance(6, 6) = slope_std * slope_std;
  q.covariance(0, 0) = 4.0 * slope_std * slope_std;
  q.covariance(0, 6) = q.covariance(6, 0) = 0.5 * 2.0 * slope_std * slope_std;
  ASSERT_TRUE(RefineCompensation(q, holds, &r));
  EXPECT_NEAR(r.slope_check_std[0], slope_std, 1e-6 * slope_std);
  EXPECT_NEAR(r.refined.xi[0], q.xi[0] + 0.5 * d_xi1, 1e-6 * d_xi1);
  EXPECT_NEAR(r.refined.covariance(6, 6), 0.5 * slope_std * slope_std,
              1e-6 * slope_std * slope_std);
  // δ1 moves by cov(δ1, ξ1)/(var(ξ1) + var(slope))·Δξ1 = 0.5·Δξ1.
  EXPECT_NEAR(r.refined.delta[0], q.delta[0] + 0.5 * d_xi1, 1e-6 * d_xi1);

  // One rate cannot separate what scales with Ω from what does not; a zero std is not a claim.
  EXPECT_FALSE(RefineCompensation(p, std::span(holds).first(1), &r));
  auto same_rate = holds;
  same_rate[1].omega_rad_s = same_rate[2].omega_rad_s = 0.3;
  EXPECT_FALSE(RefineCompensation(p, same_rate, &r));
  auto no_std = holds;
  no_std[0].bias_std_rad_s = 0.0;
  EXPECT_FALSE(RefineCompensation(p, no_std, &r));
}

}  // namespace
}  // namespace hrgbench::estimator
