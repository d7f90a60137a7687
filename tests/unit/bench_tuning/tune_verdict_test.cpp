// The tuning's verdict on results made by hand, so each outcome's cause is known: the decision
// rule's guard band (U = k·u, k = 2) worked out below for each value, the order of the causes
// (stopped, not finished, residuals unexplained, a missed bound or limit, a limit not judged).

#include "hrgbench/bench/tuning/tune_verdict.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace hrgbench::bench {
namespace {

constexpr double kRadPerSPerDegPerHour = 3.14159265358979323846 / 180.0 / 3600.0;

// Two after holds at ±0.3 rad/s, each met, consistent; the angle-dependent error `rms_deg_h` with a
// fit noise of `noise_deg_h` (one harmonic: σc = σs = noise, so the noise RMS is `noise_deg_h`).
TuneResult Tuned(double rms_deg_h = 0.1, double noise_deg_h = 0.1) {
  TuneResult r;
  r.ok = true;
  r.consistent = true;
  r.chi2 = 5.0;
  r.chi2_dof = 6;
  r.chi2_limit = 22.46;
  for (const double omega : {0.3, -0.3}) {
    OperatingHold hold;
    hold.ok = true;
    hold.omega_rad_s = omega;
    hold.fit.ok = true;
    hold.fit.angle_dependent_rms_rad_s = rms_deg_h * kRadPerSPerDegPerHour;
    hold.fit.cos_std_rad_s = {noise_deg_h * kRadPerSPerDegPerHour};
    hold.fit.sin_std_rad_s = {noise_deg_h * kRadPerSPerDegPerHour};
    r.after.push_back(hold);
    VerifiedRate v;
    v.omega_rad_s = omega;
    v.met = true;
    r.verified.push_back(v);
  }
  r.scale_factor.ok = true;
  r.scale_factor.bias_rad_s = 0.5 * kRadPerSPerDegPerHour;
  r.scale_factor.bias_std_rad_s = 0.1 * kRadPerSPerDegPerHour;
  r.scale_factor.scale_factor_error = 2e-6;
  r.scale_factor.scale_factor_error_std = 1e-6;
  return r;
}

LimitsConfig WithTune(const TuneLimits& tune) {
  LimitsConfig limits;
  limits.tune = tune;
  return limits;  // the default rule: guarded acceptance with retest, k = 2
}

TEST(TuneVerdict, WithoutLimitsTheBoundAndTheResidualsDecide) {
  const TuneVerdict v = JudgeTune(Tuned(), LimitsConfig{}, false);
  EXPECT_EQ(v.outcome, OutcomeKind::kPass) << v.reason;
  EXPECT_TRUE(v.checks.empty());
}

TEST(TuneVerdict, EachDeclaredLimitIsJudgedWithItsGuardBand) {
  TuneLimits tune;
  tune.rate_error_deg_h = 1.0;   // 0.1 + 2·0.1 = 0.3 ≤ 1: conforming at both rates
  tune.bias_deg_h = 1.0;         // 0.5 ± 0.2 inside [−1, 1]
  tune.scale_factor_ppm = 10.0;  // 2 ± 2 inside [−10, 10]
  const TuneVerdict v = JudgeTune(Tuned(), WithTune(tune), false);
  EXPECT_EQ(v.outcome, OutcomeKind::kPass) << v.reason;
  ASSERT_EQ(v.checks.size(), 4u);
  for (const TuneCheck& c : v.checks) {
    EXPECT_EQ(c.decision.status, LimitStatus::kPass) << c.decision.message;
    EXPECT_EQ(c.decision.zone, DecisionZone::kConforming);
  }
  EXPECT_NEAR(v.checks[0].value, 0.1, 1e-12);
  EXPECT_NEAR(v.checks[0].std, 0.1, 1e-12);
  EXPECT_NEAR(v.checks[0].decision.expanded_uncertainty, 0.2, 1e-12);
  EXPECT_NEAR(v.checks[3].value, 2.0, 1e-9);  // ppm
}

TEST(TuneVerdict, AnErrorBeyondItsLimitFailsAndOneWithinItsGuardBandAsksForARetest) {
  TuneLimits tune;
  tune.rate_error_deg_h = 1.0;
  // 2 − 2·0.1 = 1.8 > 1: wholly outside.
  const TuneVerdict beyond = JudgeTune(Tuned(2.0), WithTune(tune), false);
  EXPECT_EQ(beyond.outcome, OutcomeKind::kFail);
  EXPECT_EQ(beyond.checks[0].decision.zone, DecisionZone::kNonConforming);
  EXPECT_NE(beyond.reason.find("rate_error_deg_h at 0.3 rad/s"), std::string::npos)
      << beyond.reason;
  // 0.9 + 0.2 = 1.1 > 1 > 0.9 − 0.2: undecided, not accepted, retest.
  const TuneVerdict straddles = JudgeTune(Tuned(0.9), WithTune(tune), false);
  EXPECT_EQ(straddles.outcome, OutcomeKind::kFail);
  EXPECT_EQ(straddles.checks[0].decision.zone, DecisionZone::kUndecided);
  EXPECT_TRUE(straddles.checks[0].decision.retest);
  // A signed bias below −max fails too.
  TuneResult negative = Tuned();
  negative.scale_factor.bias_rad_s = -1.5 * kRadPerSPerDegPerHour;
  TuneLimits bias;
  bias.bias_deg_h = 1.0;
  EXPECT_EQ(JudgeTune(negative, WithTune(bias), false).outcome, OutcomeKind::kFail);
}

TEST(TuneVerdict, ResidualsThePredictionDoesNotExplainAreAnErrorAndNoLimitIsJudged) {
  TuneResult r = Tuned();
  r.consistent = false;
  r.chi2 = 40.0;
  TuneLimits tune;
  tune.rate_error_deg_h = 1.0;
  const TuneVerdict v = JudgeTune(r, WithTune(tune), false);
  EXPECT_EQ(v.outcome, OutcomeKind::kError);
  EXPECT_TRUE(v.checks.empty());
  EXPECT_NE(v.reason.find("chi2 40 on 6"), std::string::npos) << v.reason;
}

TEST(TuneVerdict, AMissedBoundFailsAndAStabilityLimitWithoutAHoldIsNotJudged) {
  TuneResult missed = Tuned();
  missed.verified[1].met = false;
  const TuneVerdict fail = JudgeTune(missed, LimitsConfig{}, false);
  EXPECT_EQ(fail.outcome, OutcomeKind::kFail);
  EXPECT_NE(fail.reason.find("-0.3 rad/s"), std::string::npos) << fail.reason;

  TuneLimits tune;
  tune.arw_deg_per_sqrt_h = 0.01;
  const TuneVerdict error = JudgeTune(Tuned(), WithTune(tune), false);
  EXPECT_EQ(error.outcome, OutcomeKind::kError);
  ASSERT_EQ(error.checks.size(), 1u);
  EXPECT_EQ(error.checks[0].decision.status, LimitStatus::kNotEvaluated);
  EXPECT_NE(error.reason.find("zero-rate hold"), std::string::npos) << error.reason;
}

TEST(TuneVerdict, AZeroRateHoldsFiguresAreJudgedWithTheirIntervals) {
  TuneResult r = Tuned();
  ZeroRateStability z;
  z.allan.push_back({1000, 1.0, 1e-5, 10.0, 0.9e-5, 1.1e-5});
  z.arw_known = true;
  // N = 1e-5 rad/√s = 0.0344 °/√h, u = (1.1 − 0.9)e-5 / 2 = 1e-6 rad/√s.
  z.arw_rad_per_sqrt_s = 1e-5;
  z.arw_lower = 0.9e-5;
  z.arw_upper = 1.1e-5;
  z.bias_instability_rad_s = 1e-6;
  z.bias_instability_lower = 0.8e-6;
  z.bias_instability_upper = 1.2e-6;
  z.bias_instability_reached = false;
  r.stability = z;
  TuneLimits tune;
  tune.arw_deg_per_sqrt_h = 0.05;     // 0.0344 + 2·0.00344 = 0.0413 ≤ 0.05
  tune.bias_instability_deg_h = 0.1;  // 0.206 ± 0.041 °/h: beyond 0.1 whatever the band
  const TuneVerdict v = JudgeTune(r, WithTune(tune), false);
  ASSERT_EQ(v.checks.size(), 2u);
  EXPECT_NEAR(v.checks[0].value, 1e-5 * 180.0 / 3.14159265358979323846 * 60.0, 1e-12);
  EXPECT_EQ(v.checks[0].decision.status, LimitStatus::kPass) << v.checks[0].decision.message;
  EXPECT_EQ(v.checks[1].decision.status, LimitStatus::kFail) << v.checks[1].decision.message;
  EXPECT_NE(v.checks[1].decision.message.find("a bound"), std::string::npos);
  EXPECT_EQ(v.outcome, OutcomeKind::kFail);
}

TEST(TuneVerdict, StoppedIsAbortedAndUnfinishedIsAnError) {
  EXPECT_EQ(JudgeTune(Tuned(), LimitsConfig{}, true).outcome, OutcomeKind::kAborted);
  TuneResult unfinished;
  unfinished.why = "refine hold at 0.3 rad/s: table at rate: timeout";
  const TuneVerdict v = JudgeTune(unfinished, LimitsConfig{}, false);
  EXPECT_EQ(v.outcome, OutcomeKind::kError);
  EXPECT_EQ(v.reason, unfinished.why);
}

// The asymmetry is judged only where the rates can show it; a declared limit the plan cannot judge
// is an ERROR that says which rates it needs.
TEST(TuneVerdict, TheAsymmetryIsJudgedWhenTheRatesShowItAndIsAnErrorWhenTheyCannot) {
  TuneLimits tune;
  tune.scale_factor_asymmetry_ppm = 5.0;
  TuneResult two_rates = Tuned();  // ±Ω only: not known
  const TuneVerdict unknown = JudgeTune(two_rates, WithTune(tune), false);
  EXPECT_EQ(unknown.outcome, OutcomeKind::kError) << unknown.reason;
  ASSERT_EQ(unknown.checks.size(), 1u);
  EXPECT_NE(unknown.checks[0].decision.message.find("both signs and two magnitudes"),
            std::string::npos)
      << unknown.checks[0].decision.message;
  TuneResult four_rates = Tuned();
  four_rates.scale_factor.asymmetry_known = true;
  four_rates.scale_factor.asymmetry = 3e-6;  // 3 ± 2·0.5 = [2, 4] inside [−5, 5]
  four_rates.scale_factor.asymmetry_std = 0.5e-6;
  const TuneVerdict known = JudgeTune(four_rates, WithTune(tune), false);
  EXPECT_EQ(known.outcome, OutcomeKind::kPass) << known.reason;
  ASSERT_EQ(known.checks.size(), 1u);
  EXPECT_NEAR(known.checks[0].value, 3.0, 1e-9);
  four_rates.scale_factor.asymmetry = 6e-6;  // wholly outside
  EXPECT_EQ(JudgeTune(four_rates, WithTune(tune), false).outcome, OutcomeKind::kFail);
}

}  // namespace
}  // namespace hrgbench::bench
