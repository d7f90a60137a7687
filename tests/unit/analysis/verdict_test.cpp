// EvaluateLimits: PASS inside, FAIL outside (naming the parameter), NOT EVALUATED without a value.

#include "hrgbench/analysis/verdict.hpp"

#include <gtest/gtest.h>

#include "in_model_unit.hpp"

namespace hrgbench::bench {
namespace {

using estimator::EstimateSummary;
using estimator::Termination;

using hrgbench::testing::InModelUnit;
EstimateSummary PaperUnit() { return InModelUnit(); }
LimitsConfig Limits() { return hrgbench::testing::ExampleLimits(); }

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
  s.delta_std(1) = 0.0;  // exact: the guard band is empty
  EXPECT_EQ(EvaluateLimits(Limits(), s).overall, LimitStatus::kPass);
}

// Simple acceptance with max_uncertainty_ratio 0.5 at k = 2 is the bench's rule before
// [decision] (std ≤ a quarter of the width): δ2's band [0.29, 0.31] is 0.02 wide, so a std of
// 0.005 is judged and 0.0051 is not, in or out of the band; 0.35 ± 0.01 is a FAIL (its whole
// interval [0.33, 0.37] outside).
TEST(Verdict, SimpleAcceptanceJudgesOnlyWhatTheEstimateResolvesUnlessWhollyOutside) {
  LimitsConfig limits = Limits();
  limits.decision.kind = DecisionRuleKind::kSimpleAcceptance;
  limits.decision.max_uncertainty_ratio = 0.5;
  EstimateSummary s = PaperUnit();
  s.delta_std(1) = 0.005;
  EXPECT_EQ(EvaluateLimits(limits, s).results[1].status, LimitStatus::kPass);
  s.delta_std(1) = 0.0051;
  Verdict vague = EvaluateLimits(limits, s);
  EXPECT_EQ(vague.results[1].status, LimitStatus::kNotEvaluated);
  EXPECT_NE(vague.results[1].message.find("too uncertain to judge"), std::string::npos)
      << vague.results[1].message;
  EXPECT_EQ(vague.overall, LimitStatus::kNotEvaluated);
  s.delta(1) = 0.32;  // outside by 0.01 = 2 std: could be noise
  EXPECT_EQ(EvaluateLimits(limits, s).results[1].status, LimitStatus::kNotEvaluated);
  s.delta_std(1) = 0.01;
  s.delta(1) = 0.35;
  const Verdict out = EvaluateLimits(limits, s);
  EXPECT_EQ(out.results[1].status, LimitStatus::kFail);
  EXPECT_NE(out.results[1].message.find("whole interval"), std::string::npos)
      << out.results[1].message;
  EXPECT_EQ(out.overall, LimitStatus::kFail);
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

// The fit is judged before any limit, with the defaults when the file has no [fit]: three checks
// per run here (ratio, whiteness, Ω offset).
TEST(Verdict, AFitInsideItsModelIsJudgedAndPasses) {
  const Verdict verdict = EvaluateLimits(Limits(), PaperUnit());
  ASSERT_EQ(verdict.fit_checks.size(), 6u);
  EXPECT_TRUE(verdict.fit_acceptable);
  for (const FitCheck& c : verdict.fit_checks) EXPECT_EQ(c.status, LimitStatus::kPass) << c.message;
  EXPECT_EQ(verdict.fit_checks[0].name, "residual_ratio");
  EXPECT_EQ(verdict.fit_checks[0].max, 1.05);  // 1 + 5·0.451/√1e5 = 1.0071 is below the default
  EXPECT_NE(verdict.Report().find("fit: every run within its limits (6 checks)"),
            std::string::npos);
}

// A fit outside its model: no limit is judged, not even one that would fail, and each says what it
// would have been; the verdict is NOT EVALUATED (the app's ERROR) and names the run and the check.
TEST(Verdict, AFitOutsideItsModelJudgesNoLimit) {
  EstimateSummary s = PaperUnit();
  s.delta[estimator::kScaleFactor] = 0.35;  // would FAIL
  s.diagnostics.runs[1].residual_ratio = 22.1;
  const Verdict verdict = EvaluateLimits(Limits(), s);
  EXPECT_FALSE(verdict.fit_acceptable);
  EXPECT_EQ(verdict.overall, LimitStatus::kNotEvaluated);
  for (const LimitResult& r : verdict.results) EXPECT_EQ(r.status, LimitStatus::kNotEvaluated);
  EXPECT_NE(verdict.results[1].message.find("would be FAIL"), std::string::npos)
      << verdict.results[1].message;
  EXPECT_NE(verdict.FitProblems().find("run 2: residual_ratio = 22.1 above 1.05"),
            std::string::npos)
      << verdict.FitProblems();
  EXPECT_TRUE(verdict.FailedNames().empty());
}

TEST(Verdict, ColouredResidualsAndAContradictedRateAreJudged) {
  EstimateSummary s = PaperUnit();
  s.diagnostics.runs[0].whiteness_z = 40.0;
  EXPECT_FALSE(EvaluateLimits(Limits(), s).fit_acceptable);
  s = PaperUnit();
  s.diagnostics.runs[0].omega_offset_in_std = -9.8;  // |offset| is judged
  const Verdict verdict = EvaluateLimits(Limits(), s);
  EXPECT_FALSE(verdict.fit_acceptable);
  EXPECT_NE(verdict.FitProblems().find("run 1: omega_offset_in_std = 9.8 above 4"),
            std::string::npos)
      << verdict.FitProblems();
}

// [fit] in the limits file moves the thresholds; a short run gets five standard errors of room.
TEST(Verdict, TheLimitsFilesFitTableSetsTheThresholds) {
  auto limits = ParseLimitsConfig(
      "[limits]\nname = \"t\"\n[fit]\nresidual_ratio_max = 1.5\nwhiteness_z_max = 50\n", "l.toml");
  ASSERT_TRUE(limits.has_value()) << limits.error().ToString();
  EXPECT_EQ(limits->fit_line, 3u);
  EstimateSummary s = PaperUnit();
  s.diagnostics.runs[0].residual_ratio = 1.4;
  s.diagnostics.runs[1].whiteness_z = 40.0;
  EXPECT_TRUE(EvaluateLimits(*limits, s).fit_acceptable);
  s.diagnostics.runs[0].samples = 400;  // 1 + 5·0.451/√400 = 1.113
  s.diagnostics.runs[0].residual_ratio = 1.1;
  EXPECT_TRUE(EvaluateLimits(LimitsConfig{}, s).fit_acceptable == false);  // whiteness 40 > 6
  s.diagnostics.runs[1].whiteness_z = 0.0;
  EXPECT_TRUE(EvaluateLimits(LimitsConfig{}, s).fit_acceptable);
}

TEST(Verdict, AFitTableOutOfRangeNamesTheKey) {
  const auto limits =
      ParseLimitsConfig("[limits]\nname = \"t\"\n[fit]\nresidual_ratio_max = 0.9\n", "l.toml");
  ASSERT_FALSE(limits.has_value());
  EXPECT_NE(limits.error().ToString().find("fit.residual_ratio_max"), std::string::npos)
      << limits.error().ToString();
  const auto unknown = ParseLimitsConfig("[limits]\nname = \"t\"\n[fit]\nratio = 2\n", "l.toml");
  ASSERT_FALSE(unknown.has_value());
}

// A problem the estimate names about itself as a whole (every run's residuals clean: a wrong I/Q
// convention or rate sign fits perfectly) fails the fit: never a PASS.
TEST(Verdict, AProblemOfTheWholeEstimateIsNeverAPass) {
  EstimateSummary s = PaperUnit();
  ASSERT_EQ(EvaluateLimits(Limits(), s).overall, LimitStatus::kPass);
  s.diagnostics.problems.push_back(
      "the data's quadrature at release has the opposite sign of the commanded one in every run");
  const Verdict verdict = EvaluateLimits(Limits(), s);
  EXPECT_FALSE(verdict.fit_acceptable);
  EXPECT_EQ(verdict.overall, LimitStatus::kNotEvaluated);
  EXPECT_NE(verdict.FitProblems().find("estimate: the data's quadrature"), std::string::npos)
      << verdict.FitProblems();
  // A run's own problem is the per-run checks' to judge (against this file's thresholds).
  s.diagnostics.problems = {"run 1: residuals not white (Ljung-Box z = 7, limit 6)"};
  EXPECT_EQ(EvaluateLimits(Limits(), s).overall, LimitStatus::kPass);
}

// An estimate without diagnostics (a method that reports none) cannot PASS.
TEST(Verdict, AnEstimateWithoutDiagnosticsIsNotJudged) {
  EstimateSummary s = PaperUnit();
  s.diagnostics.runs.clear();
  const Verdict verdict = EvaluateLimits(Limits(), s);
  EXPECT_EQ(verdict.overall, LimitStatus::kNotEvaluated);
  EXPECT_NE(verdict.FitProblems().find("no fit diagnostics"), std::string::npos);
}

}  // namespace
}  // namespace hrgbench::bench
