// The judge of a recorded session (session_judge.hpp): each branch of the PASS/FAIL/ERROR policy,
// a fixture's aggregate outcome and exit code, what a resume keeps; and whether a captured run is
// accepted (run_acceptance.hpp). Synthetic estimates: a converged ML summary of two in-model runs
// (tests/support/in_model_unit.hpp, shared with verdict_test.cpp).

#include "hrgbench/analysis/session_judge.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>

#include "hand_made_record.hpp"
#include "hrgbench/analysis/run_acceptance.hpp"
#include "hrgbench/session/exit_codes.hpp"
#include "in_model_unit.hpp"

namespace hrgbench::bench {
namespace {

using estimator::EstimateSummary;
using estimator::Termination;

using hrgbench::testing::InModelUnit;
LimitsConfig Limits() { return hrgbench::testing::ExampleLimits(); }

// The engineering of record without a record's f0 or pick-off declaration.
std::expected<EngineeringOfRecord, std::string> Engineering(const EstimateSummary& s) {
  EngineeringOfRecord of_record;
  of_record.quantities = estimator::ComputeEngineeringQuantities(s, estimator::kNaN);
  return of_record;
}

SessionJudgement Judge(const EstimateSummary& s, const LimitsConfig& limits = Limits()) {
  return JudgeSession(s, Engineering(s), limits);
}

TEST(SessionJudge, EveryLimitJudgedAndMetIsPass) {
  const SessionJudgement judgement = Judge(InModelUnit());
  EXPECT_EQ(judgement.kind, OutcomeKind::kPass);
  EXPECT_EQ(judgement.reason, "the fit is within its model and every limit met");
  EXPECT_TRUE(judgement.failed_parameters.empty());
  ASSERT_TRUE(judgement.verdict.has_value());
  EXPECT_EQ(judgement.verdict->overall, LimitStatus::kPass);
  EXPECT_TRUE(judgement.engineering.has_value());
}

TEST(SessionJudge, NoLimitsIsPassSayingSo) {
  const SessionJudgement judgement = Judge(InModelUnit(), LimitsConfig{});
  EXPECT_EQ(judgement.kind, OutcomeKind::kPass);
  EXPECT_EQ(judgement.reason, "the fit is within its model; no limits to judge");
}

TEST(SessionJudge, AFailedLimitIsFailNamingItAndWhatWasNotJudged) {
  EstimateSummary s = InModelUnit();
  s.delta(1) = 0.35;                  // delta2 above its max
  s.xi_estimated = estimator::kNoXi;  // xi1 held: not judged
  const SessionJudgement judgement = Judge(s);
  EXPECT_EQ(judgement.kind, OutcomeKind::kFail);
  ASSERT_EQ(judgement.failed_parameters.size(), 1u);
  EXPECT_EQ(judgement.failed_parameters[0].name, "delta2");
  EXPECT_EQ(judgement.failed_parameters[0].value, 0.35);
  EXPECT_EQ(judgement.failed_parameters[0].min, 0.29);
  EXPECT_EQ(judgement.failed_parameters[0].max, 0.31);
  EXPECT_EQ(judgement.reason.rfind("out of limits: delta2; not judged: ", 0), 0u)
      << judgement.reason;
  EXPECT_NE(judgement.reason.find("xi1"), std::string::npos) << judgement.reason;
}

TEST(SessionJudge, AFailWithEverythingJudgedSaysOnlyWhatFailed) {
  EstimateSummary s = InModelUnit();
  s.delta(0) = -0.01;
  s.delta(1) = 0.35;
  const SessionJudgement judgement = Judge(s);
  EXPECT_EQ(judgement.kind, OutcomeKind::kFail);
  EXPECT_EQ(judgement.reason, "out of limits: delta1, delta2");
  EXPECT_EQ(judgement.failed_parameters.size(), 2u);
}

TEST(SessionJudge, AnUnusableEstimateIsErrorWithTheEstimatorsMessage) {
  EstimateSummary s = InModelUnit();
  s.termination = Termination::kNumericalFailure;
  s.message = "singular information matrix";
  // The record's electronics are not even looked at.
  const SessionJudgement judgement = JudgeSession(s, std::unexpected("never read"), Limits());
  EXPECT_EQ(judgement.kind, OutcomeKind::kError);
  EXPECT_EQ(judgement.reason, "estimate not usable: singular information matrix");
  EXPECT_FALSE(judgement.verdict.has_value());
  EXPECT_FALSE(judgement.engineering.has_value());
}

TEST(SessionJudge, UnreadableElectronicsAreError) {
  const SessionJudgement judgement = JudgeSession(
      InModelUnit(), std::unexpected("field 'electronics.pickoff': expected an object"), Limits());
  EXPECT_EQ(judgement.kind, OutcomeKind::kError);
  EXPECT_EQ(judgement.reason,
            "the record's electronics: field 'electronics.pickoff': expected an object");
  EXPECT_FALSE(judgement.verdict.has_value());
}

TEST(SessionJudge, ALimitNotJudgedIsErrorNotPass) {
  EstimateSummary s = InModelUnit();
  s.xi_estimated = estimator::kNoXi;  // xi1 held fixed by the estimator
  const SessionJudgement judgement = Judge(s);
  EXPECT_EQ(judgement.kind, OutcomeKind::kError);
  EXPECT_EQ(judgement.reason.rfind("limits not judged: ", 0), 0u) << judgement.reason;
  EXPECT_NE(judgement.reason.find("xi1"), std::string::npos) << judgement.reason;
  EXPECT_TRUE(judgement.failed_parameters.empty());
  ASSERT_TRUE(judgement.verdict.has_value());  // recorded: it says which limit was not judged
  EXPECT_EQ(judgement.verdict->overall, LimitStatus::kNotEvaluated);
}

TEST(SessionJudge, AFitOutsideItsModelIsErrorJudgingNoLimit) {
  EstimateSummary s = InModelUnit();
  s.diagnostics.runs[1].residual_ratio = 22.1;
  s.delta(1) = 0.35;  // would fail; a fit outside its model judges nothing
  const SessionJudgement judgement = Judge(s);
  EXPECT_EQ(judgement.kind, OutcomeKind::kError);
  EXPECT_EQ(judgement.reason.rfind("the fit is outside its model, no limit judged: ", 0), 0u)
      << judgement.reason;
  EXPECT_NE(judgement.reason.find("run 2: residual_ratio = 22.1"), std::string::npos)
      << judgement.reason;
  EXPECT_TRUE(judgement.failed_parameters.empty());
}

TEST(SessionJudge, TheOutcomeCarriesTheVerdictAndTheCallersEstimate) {
  EstimateSummary s = InModelUnit();
  s.delta(1) = 0.35;
  const SessionOutcome outcome = Judge(s).ToOutcome(nlohmann::json{{"method", "ml"}});
  EXPECT_EQ(outcome.kind, OutcomeKind::kFail);
  EXPECT_EQ(outcome.reason, "out of limits: delta2");
  ASSERT_EQ(outcome.failed_parameters.size(), 1u);
  ASSERT_TRUE(outcome.estimate.has_value());
  EXPECT_EQ((*outcome.estimate)["method"], "ml");
  ASSERT_TRUE(outcome.verdict.has_value());
  EXPECT_TRUE(outcome.verdict->contains("limits"));
  // Without a verdict (ERROR before the limits) there is none in the record.
  EXPECT_FALSE(JudgeSession(s, std::unexpected("x"), Limits()).ToOutcome({}).verdict.has_value());
}

TEST(SessionJudge, ARecordsElectronicsAreReadOnlyForAUsableEstimate) {
  // A malformed declaration is named by the record's one reader, before any judge sees it (the
  // sequencer then closes with ERROR "the record cannot be read back: ...").
  const auto bad_electronics = session::ReadSessionRecord(
      testing::CompleteSessionDocument({{"electronics", {{"pickoff", "midway"}}}}),
      "test/session.json");
  ASSERT_FALSE(bad_electronics.has_value());
  EXPECT_EQ(bad_electronics.error().field, "electronics.pickoff");
  EstimateSummary unusable = InModelUnit();
  unusable.termination = Termination::kNumericalFailure;
  unusable.message = "diverged";
  const session::SessionRecord record = testing::RecordOf(nlohmann::json::object());
  EXPECT_EQ(JudgeRecordedSession(unusable, record, Limits()).reason,
            "estimate not usable: diverged");
  // An engineering of record that could not be computed is the bench's ERROR.
  const SessionJudgement judgement =
      JudgeSession(InModelUnit(), std::unexpected("no electronics"), Limits());
  EXPECT_EQ(judgement.kind, OutcomeKind::kError);
  EXPECT_EQ(judgement.reason.rfind("the record's electronics: ", 0), 0u) << judgement.reason;
  // A record from before the pick-off was declared is judged (midway, with a note).
  EXPECT_EQ(JudgeRecordedSession(InModelUnit(), record, Limits()).kind, OutcomeKind::kPass);
}

TEST(FixtureJudge, TheWorstUnitDecides) {
  using enum OutcomeKind;
  EXPECT_EQ(FixtureOutcome(std::array{kPass, kPass}), kPass);
  EXPECT_EQ(FixtureOutcome(std::array{kPass, kFail}), kFail);
  EXPECT_EQ(FixtureOutcome(std::array{kFail, kError, kPass}), kError);
  EXPECT_EQ(FixtureOutcome(std::array{kAborted, kError, kFail}), kAborted);
  EXPECT_EQ(FixtureOutcome({}), kPass);
}

TEST(FixtureJudge, TheExitCodeIsTheWorstUnitsFromTheOneTable) {
  using enum OutcomeKind;
  EXPECT_EQ(FixtureExitCode(std::array{kPass, kPass, kPass}), 0);
  EXPECT_EQ(FixtureExitCode(std::array{kPass, kFail}), 1);
  EXPECT_EQ(FixtureExitCode(std::array{kFail, kError}), 2);
  EXPECT_EQ(FixtureExitCode(std::array{kError, kAborted, kPass}), 3);
  EXPECT_EQ(FixtureExitCode({}), kExitOk);
}

TEST(ExitCodes, OneTableForEveryProgram) {
  EXPECT_EQ(ExitCode(OutcomeKind::kPass), kExitOk);
  EXPECT_EQ(ExitCode(OutcomeKind::kFail), kExitFail);
  EXPECT_EQ(ExitCode(OutcomeKind::kError), kExitError);
  EXPECT_EQ(ExitCode(OutcomeKind::kAborted), kExitAborted);
  // The numbers are a contract (scripts, the line's controller, every record written so far).
  const std::array<int, 5> table = {kExitOk, kExitFail, kExitError, kExitAborted, kExitBadInput};
  EXPECT_EQ(table, (std::array<int, 5>{0, 1, 2, 3, 4}));
  EXPECT_NE(kExitCodesHelp.find("4 bad input"), std::string_view::npos);
}

TEST(KeptVerdict, AResumeKeepsAClosedPassOrFailOnly) {
  EXPECT_TRUE(KeepsVerdict(true, OutcomeKind::kPass));
  EXPECT_TRUE(KeepsVerdict(true, OutcomeKind::kFail));
  EXPECT_FALSE(KeepsVerdict(true, OutcomeKind::kError));  // the bench owes it a verdict
  EXPECT_FALSE(KeepsVerdict(true, OutcomeKind::kAborted));
  EXPECT_FALSE(KeepsVerdict(false, OutcomeKind::kPass));  // not closed: it continues
  EXPECT_EQ(KeptReason("out of limits: delta2"), "kept from before: out of limits: delta2");
}

TEST(KeptVerdict, OutcomeKindsReadBackAsWritten) {
  for (const OutcomeKind kind :
       {OutcomeKind::kPass, OutcomeKind::kFail, OutcomeKind::kError, OutcomeKind::kAborted})
    EXPECT_EQ(ParseOutcomeKind(ToString(kind)), kind);
  EXPECT_FALSE(ParseOutcomeKind("pass").has_value());
  EXPECT_FALSE(ParseOutcomeKind("").has_value());
}

TEST(RunAcceptance, DropsWithinTheAllowanceAreAccepted) {
  CaptureCriteria capture;
  capture.max_sequence_gaps = 2;
  capture.max_samples_lost = 10;
  EXPECT_FALSE(TooManyDrops(3, 2, 10, capture).has_value());
  EXPECT_EQ(TooManyDrops(3, 3, 10, capture),
            "too many drops in run 3: 3 gaps, 10 samples lost (allowed 2, 10)");
  EXPECT_EQ(TooManyDrops(4, 0, 11, capture),
            "too many drops in run 4: 0 gaps, 11 samples lost (allowed 2, 10)");
  EXPECT_TRUE(TooManyDrops(1, 1, 0, CaptureCriteria{}).has_value());  // the default: none
}

TEST(RunAcceptance, DriftIsFlaggedOrRejectedAsDeclared) {
  DriftCriteria drift;  // 1 % of temperature, frequency not checked, flag
  EXPECT_EQ(JudgeRunDrift(25.0, 25.2, 5000.0, 5100.0, drift).drift, RunDrift::kSteady);
  const RunDriftJudgement warm = JudgeRunDrift(25.0, 25.5, 5000.0, 5000.0, drift);
  EXPECT_EQ(warm.drift, RunDrift::kFlagged);
  EXPECT_EQ(warm.what, "temperature changed by 2 %");
  drift.max_frequency_change_rel = 1e-3;
  drift.action = DriftAction::kReject;
  const RunDriftJudgement both = JudgeRunDrift(25.0, 25.5, 5000.0, 5010.0, drift);
  EXPECT_EQ(both.drift, RunDrift::kRejected);
  EXPECT_EQ(both.what, "temperature changed by 2 %, resonant frequency changed by 0.2 %");
  // No reading (NaN) or a zero start: nothing to compare, nothing judged.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(JudgeRunDrift(nan, 30.0, 0.0, 5010.0, drift).drift, RunDrift::kSteady);
  EXPECT_EQ(RelativeChange(0.0, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(RelativeChange(-2.0, -1.0), 0.5);
}

}  // namespace
}  // namespace hrgbench::bench
