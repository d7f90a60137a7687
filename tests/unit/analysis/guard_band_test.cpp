// The decision rule with guard bands (config/decision_rule.hpp, analysis/verdict.hpp): issue 26's
// good unit that FAILed on ξ1 = 0.0244 ± 0.0095 against ±0.02, a clear PASS, a wholly-outside
// FAIL, the reject and simple-acceptance rules, a magnitude's unguarded physical bound, the
// session's outcome and reason, and the record's round trip of the new fields.

#include <gtest/gtest.h>

#include <cmath>

#include "hand_made_record.hpp"
#include "hrgbench/analysis/session_judge.hpp"
#include "hrgbench/analysis/verdict.hpp"
#include "hrgbench/analysis/verdict_json.hpp"
#include "in_model_unit.hpp"

namespace hrgbench::bench {
namespace {

using estimator::EstimateSummary;

LimitsConfig Limits() { return hrgbench::testing::ExampleLimits(); }  // xi1 = [-0.02, 0.02]

EstimateSummary WithXi1(double value, double std) {
  EstimateSummary s = hrgbench::testing::InModelUnit();
  s.xi(0) = value;
  s.xi_std(0) = std;
  return s;
}

const LimitResult& Xi1(const Verdict& verdict) { return verdict.results[2]; }

SessionJudgement Judge(const EstimateSummary& s, const LimitsConfig& limits) {
  EngineeringOfRecord of_record;
  of_record.quantities = estimator::ComputeEngineeringQuantities(s, estimator::kNaN);
  return JudgeSession(s, of_record, limits);
}

// Issue 26: ξ1 = 0.0244 ± 0.0095 (truth 0.01) was a FAIL on its point value. Its interval at
// k = 2, [0.0054, 0.0434], straddles 0.02: neither conformance nor non-conformance is proven, so
// the default rule (guarded acceptance with retest) does not accept the unit and sends it to a
// retest; it is not a FAIL the unit earned.
TEST(GuardBand, TheIssuesGoodUnitIsUndecidedAndGoesToRetest) {
  ASSERT_EQ(Xi1(EvaluateLimits(Limits(), WithXi1(0.01, 1e-5))).status, LimitStatus::kPass);
  const Verdict verdict = EvaluateLimits(Limits(), WithXi1(0.0244, 0.0095));
  const LimitResult& r = Xi1(verdict);
  EXPECT_EQ(r.zone, DecisionZone::kUndecided) << r.message;
  EXPECT_EQ(r.rule, DecisionRuleKind::kGuardedAcceptanceRetest);
  EXPECT_TRUE(r.retest);
  EXPECT_DOUBLE_EQ(r.coverage_factor, 2.0);
  EXPECT_DOUBLE_EQ(r.expanded_uncertainty, 0.019);
  EXPECT_NEAR(r.interval_min, 0.0054, 1e-12);
  EXPECT_NEAR(r.interval_max, 0.0434, 1e-12);
  EXPECT_NEAR(r.acceptance_min, -0.001, 1e-12);
  EXPECT_NEAR(r.acceptance_max, 0.001, 1e-12);
  EXPECT_NE(r.message.find("retest"), std::string::npos) << r.message;
  EXPECT_TRUE(verdict.retest);
  const SessionJudgement judgement = Judge(WithXi1(0.0244, 0.0095), Limits());
  EXPECT_EQ(judgement.kind, OutcomeKind::kFail);
  EXPECT_EQ(judgement.reason.find("out of limits"), std::string::npos) << judgement.reason;
  EXPECT_NE(judgement.reason.find("not accepted within the guard band (k = 2): xi1, retest"),
            std::string::npos)
      << judgement.reason;
}

// A value inside the limits whose interval straddles one is not a PASS either.
TEST(GuardBand, AValueInsideWithAStraddlingIntervalIsNotAPass) {
  const LimitResult r = Xi1(EvaluateLimits(Limits(), WithXi1(0.015, 0.004)));
  EXPECT_EQ(r.zone, DecisionZone::kUndecided) << r.message;
  EXPECT_EQ(r.status, LimitStatus::kFail);
}

TEST(GuardBand, AnIntervalClearlyInsideIsPass) {
  const Verdict verdict = EvaluateLimits(Limits(), WithXi1(0.01, 0.004));
  EXPECT_EQ(Xi1(verdict).zone, DecisionZone::kConforming) << Xi1(verdict).message;
  EXPECT_EQ(verdict.overall, LimitStatus::kPass);
  EXPECT_FALSE(verdict.retest);
}

TEST(GuardBand, AnIntervalWhollyOutsideIsFailWithoutRetest) {
  const Verdict verdict = EvaluateLimits(Limits(), WithXi1(0.04, 0.008));  // [0.024, 0.056]
  EXPECT_EQ(Xi1(verdict).zone, DecisionZone::kNonConforming) << Xi1(verdict).message;
  EXPECT_EQ(Xi1(verdict).status, LimitStatus::kFail);
  EXPECT_FALSE(Xi1(verdict).retest);
  EXPECT_FALSE(verdict.retest);
  const SessionJudgement judgement = Judge(WithXi1(0.04, 0.008), Limits());
  EXPECT_NE(judgement.reason.find("out of limits: xi1"), std::string::npos) << judgement.reason;
  EXPECT_EQ(judgement.reason.find("retest"), std::string::npos) << judgement.reason;
}

// One proven FAIL makes a retest pointless, whatever else is undecided.
TEST(GuardBand, AProvenFailOutranksAnUndecidedLimit) {
  EstimateSummary s = WithXi1(0.0244, 0.0095);
  s.delta(1) = 0.4;  // delta2 = [0.29, 0.31], std 1e-6
  const Verdict verdict = EvaluateLimits(Limits(), s);
  EXPECT_EQ(verdict.overall, LimitStatus::kFail);
  EXPECT_FALSE(verdict.retest);
}

TEST(GuardBand, TheRejectRuleRejectsAnUndecidedUnitWithoutRetest) {
  LimitsConfig limits = Limits();
  limits.decision.kind = DecisionRuleKind::kGuardedAcceptanceReject;
  const Verdict verdict = EvaluateLimits(limits, WithXi1(0.0244, 0.0095));
  EXPECT_EQ(Xi1(verdict).zone, DecisionZone::kUndecided);
  EXPECT_EQ(Xi1(verdict).status, LimitStatus::kFail);
  EXPECT_FALSE(Xi1(verdict).retest);
  EXPECT_FALSE(verdict.retest);
  EXPECT_NE(Xi1(verdict).message.find("rejected"), std::string::npos) << Xi1(verdict).message;
}

TEST(GuardBand, TheCoverageFactorSetsTheGuard) {
  LimitsConfig limits = Limits();
  limits.decision.coverage_factor = 1.0;  // U = 0.004: [0.011, 0.019] inside
  EXPECT_EQ(Xi1(EvaluateLimits(limits, WithXi1(0.015, 0.004))).zone, DecisionZone::kConforming);
  limits.decision.coverage_factor = 3.0;  // U = 0.012: [0.003, 0.027]
  EXPECT_EQ(Xi1(EvaluateLimits(limits, WithXi1(0.015, 0.004))).zone, DecisionZone::kUndecided);
}

// 2·U wider than the tolerance: no retest can ever accept the unit, so the bench did not judge it.
TEST(GuardBand, AnEmptyAcceptanceZoneIsNotEvaluated) {
  const Verdict verdict = EvaluateLimits(Limits(), WithXi1(0.0, 0.011));  // 2·0.022 > 0.04
  EXPECT_EQ(Xi1(verdict).status, LimitStatus::kNotEvaluated) << Xi1(verdict).message;
  EXPECT_EQ(Xi1(verdict).zone, DecisionZone::kNotJudged);
  EXPECT_NE(Xi1(verdict).message.find("conformance cannot be proven"), std::string::npos);
}

TEST(GuardBand, SimpleAcceptanceJudgesThePointValue) {
  LimitsConfig limits = Limits();
  limits.decision.kind = DecisionRuleKind::kSimpleAcceptance;
  limits.decision.max_uncertainty_ratio = 0.5;
  const LimitResult r = Xi1(EvaluateLimits(limits, WithXi1(0.015, 0.004)));
  EXPECT_EQ(r.zone, DecisionZone::kConforming) << r.message;
  EXPECT_EQ(r.status, LimitStatus::kPass);
  EXPECT_DOUBLE_EQ(r.acceptance_max, 0.02);
  EXPECT_EQ(Xi1(EvaluateLimits(limits, WithXi1(0.0244, 0.0095))).status, LimitStatus::kFail);
}

// A magnitude cannot be below 0: the frequency split's lower limit 0 is the physics, not a
// tolerance, so a split near 0 whose interval reaches below 0 is still a PASS (guarded only
// at max); a decay time's lower limit above 0 is guarded.
TEST(GuardBand, AMagnitudesPhysicalBoundIsNotGuarded) {
  EXPECT_EQ(PhysicalMinimum(LimitedQuantity::kXi1), -std::numeric_limits<double>::infinity());
  EXPECT_EQ(PhysicalMinimum(LimitOf(estimator::EngineeringQuantity::kFrequencySplit)), 0.0);
  EXPECT_EQ(PhysicalMinimum(LimitedQuantity::kResidualRms), 0.0);
  auto limits = ParseLimitsConfig(
      "[limits]\nname = \"t\"\nfrequency_split_mhz = [0.0, 0.5]\ntau_s = [500.0, 2000.0]\n",
      "l.toml");
  ASSERT_TRUE(limits.has_value());
  EstimateSummary s = hrgbench::testing::InModelUnit();
  estimator::EngineeringQuantities e = estimator::ComputeEngineeringQuantities(s, estimator::kNaN);
  auto& split = e[estimator::EngineeringQuantity::kFrequencySplit];
  split.determined = true;
  split.value = 0.02;
  split.std = 0.03;  // interval [-0.04, 0.08]
  auto& tau = e[estimator::EngineeringQuantity::kDecayTime];
  tau.determined = true;
  tau.value = 520.0;
  tau.std = 20.0;  // interval [480, 560] straddles 500
  const Verdict verdict = EvaluateLimits(*limits, s, e);
  ASSERT_EQ(verdict.results.size(), 2u);
  const LimitResult& tau_result = verdict.results[0];
  const LimitResult& split_result = verdict.results[1];
  EXPECT_EQ(split_result.zone, DecisionZone::kConforming) << split_result.message;
  EXPECT_DOUBLE_EQ(split_result.acceptance_min, 0.0);
  EXPECT_DOUBLE_EQ(split_result.acceptance_max, 0.44);
  EXPECT_EQ(tau_result.zone, DecisionZone::kUndecided) << tau_result.message;
  EXPECT_DOUBLE_EQ(tau_result.acceptance_min, 540.0);
}

TEST(GuardBand, TheLimitsFileDeclaresTheRuleAndItsCoverageFactor) {
  const auto absent = ParseLimitsConfig("[limits]\nname = \"t\"\n", "l.toml");
  ASSERT_TRUE(absent.has_value());
  EXPECT_EQ(absent->decision.kind, DecisionRuleKind::kGuardedAcceptanceRetest);
  EXPECT_EQ(absent->decision.coverage_factor, 2.0);
  EXPECT_EQ(absent->decision.line, 0u);
  const auto declared = ParseLimitsConfig(
      "[limits]\nname = \"t\"\n[decision]\nrule = \"simple_acceptance\"\n"
      "coverage_factor = 3\nmax_uncertainty_ratio = 0.125\n",
      "l.toml");
  ASSERT_TRUE(declared.has_value()) << declared.error().ToString();
  EXPECT_EQ(declared->decision.kind, DecisionRuleKind::kSimpleAcceptance);
  EXPECT_EQ(declared->decision.coverage_factor, 3.0);
  EXPECT_EQ(declared->decision.max_uncertainty_ratio, 0.125);
  EXPECT_EQ(declared->decision.line, 3u);
  const auto reject = ParseLimitsConfig(
      "[limits]\nname = \"t\"\n[decision]\nrule = \"guarded_acceptance_reject\"\n", "l.toml");
  ASSERT_TRUE(reject.has_value());
  EXPECT_EQ(reject->decision.kind, DecisionRuleKind::kGuardedAcceptanceReject);
}

// The verdict's decision fields survive session.json: written by VerdictJson, read back by the
// record's one reader.
TEST(GuardBand, TheDecisionRoundTripsThroughTheRecord) {
  LimitsConfig limits = Limits();
  limits.decision.kind = DecisionRuleKind::kGuardedAcceptanceRetest;
  limits.decision.coverage_factor = 1.5;
  const Verdict verdict = EvaluateLimits(limits, WithXi1(0.0244, 0.0095));
  const session::SessionRecord record = hrgbench::testing::RecordOf(
      {{"outcome", {{"kind", "FAIL"}, {"reason", "r"}, {"verdict", VerdictJson(verdict)}}}});
  ASSERT_TRUE(record.outcome && record.outcome->verdict);
  const session::VerdictRecord& v = *record.outcome->verdict;
  EXPECT_EQ(v.decision_rule, "guarded_acceptance_retest");
  EXPECT_DOUBLE_EQ(v.decision_coverage_factor, 1.5);
  EXPECT_TRUE(std::isnan(v.decision_max_uncertainty_ratio));
  EXPECT_EQ(v.retest, std::optional<bool>(true));
  ASSERT_EQ(v.limits.size(), 4u);
  const session::LimitRowRecord& row = v.limits[2];
  EXPECT_EQ(row.quantity, "xi1");
  EXPECT_EQ(row.rule, "guarded_acceptance_retest");
  EXPECT_EQ(row.zone, "undecided");
  EXPECT_DOUBLE_EQ(row.coverage_factor, 1.5);
  EXPECT_DOUBLE_EQ(row.expanded_uncertainty, Xi1(verdict).expanded_uncertainty);
  EXPECT_DOUBLE_EQ(row.interval_min, Xi1(verdict).interval_min);
  EXPECT_DOUBLE_EQ(row.interval_max, Xi1(verdict).interval_max);
  EXPECT_DOUBLE_EQ(row.acceptance_min, Xi1(verdict).acceptance_min);
  EXPECT_DOUBLE_EQ(row.acceptance_max, Xi1(verdict).acceptance_max);
  EXPECT_EQ(row.retest, std::optional<bool>(true));
  // A record from before [decision] reads with the fields empty, not as an error.
  const session::SessionRecord old = hrgbench::testing::RecordOf(
      {{"outcome",
        {{"kind", "PASS"},
         {"verdict",
          {{"overall", "PASS"},
           {"limits", {{{"quantity", "xi1"}, {"status", "PASS"}, {"value", 0.01}}}}}}}}});
  ASSERT_TRUE(old.outcome && old.outcome->verdict);
  EXPECT_EQ(old.outcome->verdict->decision_rule, "");
  EXPECT_FALSE(old.outcome->verdict->retest.has_value());
  EXPECT_EQ(old.outcome->verdict->limits[0].zone, "");
  EXPECT_TRUE(std::isnan(old.outcome->verdict->limits[0].interval_min));
}

}  // namespace
}  // namespace hrgbench::bench
