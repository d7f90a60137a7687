// What a run plan can and cannot determine, before and during a fit.
#include "hrgbench/estimator/identifiability.hpp"

#include <gtest/gtest.h>

#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/simulation.hpp"

namespace hrgbench::estimator {
namespace {

std::vector<RunData> Simulate(const std::vector<double>& omegas,
                              const Xi& xi = Xi(0.01, 0.002, -0.003, 0.004)) {
  std::vector<RunPlan> plans;
  for (std::size_t k = 0; k < omegas.size(); ++k) {
    RunPlan p;
    p.omega_rad_s = omegas[k];
    p.b = -0.4 + 0.2 * static_cast<double>(k % 5);
    p.theta_rad = 0.45 * static_cast<double>(k);
    p.duration_s = 10.0;
    plans.push_back(p);
  }
  SimulationOptions options;
  options.delta << -1e-3, 0.3, 1e-6, -2e-6, 3e-6, 1e-6;
  options.xi = xi;
  return SimulateRuns(plans, options);
}

TEST(IdentifiabilityTest, RatePlanRules) {
  const IdentifiabilityReport good = CheckRatePlan({-0.1, 0.1, 0.3}, kAllXi);
  EXPECT_TRUE(good.AllIdentifiable(kAllXi));
  EXPECT_EQ(good.distinct_omegas, 3);
  EXPECT_TRUE(good.reasons.empty());

  const IdentifiabilityReport one_rate = CheckRatePlan({0.2, 0.2, 0.2}, kAllXi);
  EXPECT_TRUE(one_rate.delta_identifiable[kScaleFactor]);
  EXPECT_EQ(one_rate.xi_identifiable, kNoXi);
  ASSERT_EQ(one_rate.reasons.size(), 1u);
  EXPECT_NE(one_rate.reasons[0].find("one Ω"), std::string::npos);

  const IdentifiabilityReport at_rest = CheckRatePlan({0.0, 0.0}, kAllXi);
  EXPECT_FALSE(at_rest.delta_identifiable[kScaleFactor]);
  EXPECT_EQ(at_rest.xi_identifiable, kNoXi);
  EXPECT_EQ(at_rest.reasons.size(), 2u);

  // ξ not requested: one rate is no problem.
  EXPECT_TRUE(CheckRatePlan({0.2, 0.2}, kNoXi).AllIdentifiable(kNoXi));
}

TEST(IdentifiabilityTest, InformationRankFindsTheNullDirection) {
  // Parameters 1 and 2 carry the same information (a duplicated column): one of them must go.
  Eigen::MatrixXd j(5, 3);
  j << 1, 2, 2.000000000001, 0, 1, 1, 3, 0, 0, 1, 1, 1, 2, 5, 5;
  IdentifiabilityReport report;
  const double condition =
      CheckInformation(j.transpose() * j, {true, true, true, false, false, false}, kNoXi,
                       IdentifiabilityOptions{}, &report);
  EXPECT_LT(condition, 1e10);
  EXPECT_TRUE(report.delta_identifiable[0]);
  EXPECT_NE(report.delta_identifiable[1], report.delta_identifiable[2]);
  EXPECT_EQ(report.reasons.size(), 1u);
}

// The classic case: every run at one Ω. ξ cannot be separated from δ3…δ6; the default policy
// holds ξ and says so, the refuse policy returns no numbers.
TEST(IdentifiabilityTest, OneRateHoldsXiOrRefuses) {
  const std::vector<RunData> runs = Simulate({0.2, 0.2, 0.2, 0.2});
  const EstimateSummary held = EstimateMaximumLikelihood(runs);
  ASSERT_TRUE(held.IsUsable()) << held.Report();
  EXPECT_EQ(held.xi_estimated, kNoXi);
  EXPECT_EQ(held.xi, Xi::Zero());
  ASSERT_FALSE(held.warnings.empty());
  EXPECT_NE(held.warnings[0].find("one Ω"), std::string::npos);

  MlOptions refuse;
  refuse.unidentifiable = UnidentifiablePolicy::kRefuse;
  const EstimateSummary refused = EstimateMaximumLikelihood(runs, refuse);
  EXPECT_EQ(refused.termination, Termination::kNotIdentifiable);
  EXPECT_TRUE(refused.delta.array().isNaN().all());
}

TEST(IdentifiabilityTest, RestOnlyHoldsTheScaleFactor) {
  MlOptions options;
  options.delta_fixed[kScaleFactor] = 0.25;
  // ξ = 0 in the truth: held at 0, the model is then exact (with anisotropy, ξ would have a small
  // effect even at Ω = 0 that a held ξ cannot follow).
  const EstimateSummary s =
      EstimateMaximumLikelihood(Simulate({0.0, 0.0, 0.0}, Xi::Zero()), options);
  ASSERT_TRUE(s.IsUsable()) << s.Report();
  EXPECT_FALSE(s.delta_estimated[kScaleFactor]);
  EXPECT_EQ(s.delta[kScaleFactor], 0.25);
  EXPECT_TRUE(std::isnan(s.delta_std[kScaleFactor]));
  // δ1 is still estimated, and exactly (Ω = 0 removes δ2's only effect).
  EXPECT_NEAR(s.delta[kDamping], -1e-3, 1e-12);
}

}  // namespace
}  // namespace hrgbench::estimator
