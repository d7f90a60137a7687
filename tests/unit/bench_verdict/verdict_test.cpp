// EvaluateLimits: PASS inside, FAIL outside (naming the parameter), NOT EVALUATED without a value.

#include "hrgbench/bench/verdict.hpp"

#include <gtest/gtest.h>

namespace hrgbench::bench {
namespace {

using estimator::EstimateSummary;
using estimator::Termination;

EstimateSummary PaperUnit() {
  EstimateSummary s;
  s.method = "ml";
  s.termination = Termination::kConverged;
  s.message = "converged";
  s.delta << -0.001, 0.3, 1e-7, -2e-7, 3e-7, 0.0;
  s.delta_std = estimator::Delta::Constant(1e-6);
  s.delta_estimated = {true, true, true, true, true, true};
  s.xi << 0.01, 0.0, 0.0, 0.0;
  s.xi_std = estimator::Xi::Constant(1e-5);
  s.xi_estimated = estimator::kAllXi;
  s.residual_rms = 1.0e-4;
  s.noise_sigma = 1.0e-4;
  return s;
}

LimitsConfig Limits() {
  auto limits = ParseLimitsConfig(
      "[limits]\nname = \"t\"\ndelta1 = [-0.002, -0.0005]\ndelta2 = [0.29, 0.31]\n"
      "xi1 = [-0.02, 0.02]\nresidual_rms = [0.0, 5e-4]\n",
      "l.toml");
  EXPECT_TRUE(limits.has_value());
  return *limits;
}

TEST(Verdict, AllInsideIsPass) {
  const Verdict verdict = EvaluateLimits(Limits(), PaperUnit());
  EXPECT_EQ(verdict.overall, LimitStatus::kPass);
  ASSERT_EQ(verdict.results.size(), 4u);
  for (const LimitResult& r : verdict.results) EXPECT_EQ(r.status, LimitStatus::kPass) << r.message;
  EXPECT_EQ(verdict.results[1].quantity, LimitedQuantity::kDelta2);
  EXPECT_EQ(verdict.results[1].value, 0.3);
  EXPECT_EQ(verdict.results[1].min, 0.29);
  EXPECT_EQ(verdict.results[1].max, 0.31);
  EXPECT_TRUE(verdict.FailedNames().empty());
  EXPECT_NE(verdict.Report().find("verdict: PASS"), std::string::npos);
}

TEST(Verdict, ScaleFactorAboveMaxIsFailNamingIt) {
  EstimateSummary s = PaperUnit();
  s.delta(1) = 0.35;
  const Verdict verdict = EvaluateLimits(Limits(), s);
  EXPECT_EQ(verdict.overall, LimitStatus::kFail);
  EXPECT_EQ(verdict.results[1].status, LimitStatus::kFail);
  EXPECT_EQ(verdict.results[1].value, 0.35);
  EXPECT_NE(verdict.results[1].message.find("delta2 = 0.35"), std::string::npos)
      << verdict.results[1].message;
  EXPECT_NE(verdict.results[1].message.find("outside [0.29, 0.31]"), std::string::npos);
  EXPECT_NE(verdict.results[1].message.find("above max"), std::string::npos);
  EXPECT_EQ(verdict.FailedNames(), (std::vector<std::string_view>{"delta2"}));
  EXPECT_NE(verdict.Report().find("verdict: FAIL (delta2)"), std::string::npos) << verdict.Report();
  // The others still pass.
  EXPECT_EQ(verdict.results[0].status, LimitStatus::kPass);
}

TEST(Verdict, BelowMinAndResidualAreJudgedToo) {
  EstimateSummary s = PaperUnit();
  s.xi(0) = -0.05;
  s.residual_rms = 1e-3;
  const Verdict verdict = EvaluateLimits(Limits(), s);
  EXPECT_EQ(verdict.FailedNames(), (std::vector<std::string_view>{"xi1", "residual_rms"}));
  EXPECT_NE(verdict.results[2].message.find("below min"), std::string::npos);
}

TEST(Verdict, BoundsAreInclusive) {
  EstimateSummary s = PaperUnit();
  s.delta(1) = 0.31;
  EXPECT_EQ(EvaluateLimits(Limits(), s).overall, LimitStatus::kPass);
}

TEST(Verdict, HeldFixedParameterIsNotEvaluatedNotPassed) {
  EstimateSummary s = PaperUnit();
  s.xi_estimated = estimator::kNoXi;  // held at 0.01 by the estimator
  const Verdict verdict = EvaluateLimits(Limits(), s);
  EXPECT_EQ(verdict.results[2].status, LimitStatus::kNotEvaluated);
  EXPECT_EQ(verdict.overall, LimitStatus::kNotEvaluated);
}

TEST(Verdict, FailOutranksNotEvaluated) {
  EstimateSummary s = PaperUnit();
  s.xi_estimated = estimator::kNoXi;
  s.delta(0) = -0.01;
  EXPECT_EQ(EvaluateLimits(Limits(), s).overall, LimitStatus::kFail);
}

TEST(Verdict, UnusableEstimateEvaluatesNothing) {
  EstimateSummary s = PaperUnit();
  s.termination = Termination::kNumericalFailure;
  const Verdict verdict = EvaluateLimits(Limits(), s);
  EXPECT_EQ(verdict.overall, LimitStatus::kNotEvaluated);
  for (const LimitResult& r : verdict.results) EXPECT_EQ(r.status, LimitStatus::kNotEvaluated);
}

TEST(Verdict, NoLimitsIsPass) {
  EXPECT_EQ(EvaluateLimits(LimitsConfig{}, PaperUnit()).overall, LimitStatus::kPass);
}

}  // namespace
}  // namespace hrgbench::bench
