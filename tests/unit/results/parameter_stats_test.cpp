// Line statistics on hand-made samples: ISO weeks at year boundaries (expected values from
// Python's datetime.date.isocalendar), one-sided limits, a single sample, the newest limits in
// force.
#include "hrgbench/results/parameter_stats.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using namespace hrgbench::results;

ParameterSample Sample(std::string utc, double value, std::string status = "",
                       std::optional<double> min = std::nullopt,
                       std::optional<double> max = std::nullopt) {
  ParameterSample s;
  s.started_utc = std::move(utc);
  s.value = value;
  s.limit_status = std::move(status);
  s.limit_min = min;
  s.limit_max = max;
  return s;
}

TEST(IsoWeek, YearBoundariesFollowIso8601) {
  EXPECT_EQ(IsoWeek("2026-01-01T00:00:00Z"), "2026-W01");  // a Thursday
  EXPECT_EQ(IsoWeek("2027-01-01T12:00:00Z"), "2026-W53");  // a Friday: last year's week
  EXPECT_EQ(IsoWeek("2024-12-30T08:00:00Z"), "2025-W01");  // a Monday: next year's week
  EXPECT_EQ(IsoWeek("2021-01-03"), "2020-W53");
  EXPECT_EQ(IsoWeek("2026-11-23T21:42:24.805568Z"), "2026-W48");
  EXPECT_EQ(IsoWeek("2026-02-30"), "");
  EXPECT_EQ(IsoWeek("yesterday"), "");
}

TEST(ParameterStats, OneSampleHasNoSpreadAndNoCapability) {
  const ParameterStats st =
      ComputeParameterStats("tau_s", {Sample("2026-11-02", 1000.0, "PASS", 900.0, 1100.0)});
  EXPECT_EQ(st.n, 1u);
  EXPECT_EQ(st.mean, 1000.0);
  EXPECT_EQ(st.std, 0.0);
  EXPECT_FALSE(st.cp.has_value());
  EXPECT_FALSE(st.cpk.has_value());
  ASSERT_TRUE(st.yield.has_value());
  EXPECT_EQ(*st.yield, 1.0);
}

TEST(ParameterStats, TheNewestSessionsLimitsAreInForceAndOneSidedLimitsGiveCpkOnly) {
  // Values 1, 2, 3: mean 2, sample std 1. The first session judged against [0, 10], the newest
  // (by start, whatever the order given) against an upper limit of 5 only.
  const ParameterStats st = ComputeParameterStats(
      "q", {Sample("2026-11-03", 2.0, "PASS", std::nullopt, 5.0),
            Sample("2026-11-02", 1.0, "PASS", 0.0, 10.0), Sample("2026-11-04", 3.0, "")});
  EXPECT_EQ(st.n, 3u);
  EXPECT_DOUBLE_EQ(st.mean, 2.0);
  EXPECT_DOUBLE_EQ(st.std, 1.0);
  EXPECT_FALSE(st.limit_min.has_value());
  ASSERT_TRUE(st.limit_max.has_value());
  EXPECT_EQ(*st.limit_max, 5.0);
  // One-sided: Cpu alone (Cp and Cpk are not defined for one limit).
  EXPECT_FALSE(st.cp.has_value());
  EXPECT_FALSE(st.cpk.has_value());
  EXPECT_FALSE(st.cpl.has_value());
  ASSERT_TRUE(st.cpu.has_value());
  EXPECT_DOUBLE_EQ(*st.cpu, (5.0 - 2.0) / 3.0);
  EXPECT_EQ(st.capability, "Cpu");
  EXPECT_EQ(st.judged, 2u);  // the third had no verdict on q
  EXPECT_DOUBLE_EQ(*st.yield, 1.0);
  ASSERT_EQ(st.weeks.size(), 1u);
  EXPECT_EQ(st.weeks[0].week, "2026-W45");
}

// Issue 26: frequency_split_mhz against [0, 0.5] gave a two-sided Cpk of 0.237 (the distance to 0,
// a split's natural bound, read as a process fault). A magnitude limited [0, max] is one-sided.
TEST(ParameterStats, AMagnitudeLimitedFromZeroIsOneSidedCpu) {
  // Values 0.01, 0.02, 0.03: mean 0.02, sample std 0.01.
  const ParameterStats st =
      ComputeParameterStats("frequency_split_mhz", {Sample("2026-11-02", 0.01, "PASS", 0.0, 0.5),
                                                    Sample("2026-11-03", 0.02, "PASS", 0.0, 0.5),
                                                    Sample("2026-11-04", 0.03, "PASS", 0.0, 0.5)});
  EXPECT_EQ(st.capability, "Cpu");
  ASSERT_TRUE(st.cpu.has_value());
  EXPECT_NEAR(*st.cpu, (0.5 - 0.02) / 0.03, 1e-12);
  EXPECT_FALSE(st.cpk.has_value());
  EXPECT_FALSE(st.cp.has_value());
  EXPECT_FALSE(st.cpl.has_value());
  // A lower limit of 0 on a signed quantity that goes below it is a real limit: two-sided.
  const ParameterStats signed_q =
      ComputeParameterStats("xi1", {Sample("2026-11-02", -0.01, "PASS", 0.0, 0.5),
                                    Sample("2026-11-03", 0.0, "PASS", 0.0, 0.5),
                                    Sample("2026-11-04", 0.01, "PASS", 0.0, 0.5)});
  EXPECT_EQ(signed_q.capability, "Cpk");
  ASSERT_TRUE(signed_q.cpk && signed_q.cp && signed_q.cpl);
  EXPECT_NEAR(*signed_q.cpk, 0.0, 1e-12);  // min(Cpu, Cpl) with the mean on the lower limit
  EXPECT_NEAR(*signed_q.cp, 0.5 / 0.06, 1e-12);
  // A lower limit alone: Cpl.
  const ParameterStats lower = ComputeParameterStats(
      "tau_s",
      {Sample("2026-11-02", 900.0, "PASS", 500.0), Sample("2026-11-03", 1100.0, "PASS", 500.0)});
  EXPECT_EQ(lower.capability, "Cpl");
  ASSERT_TRUE(lower.cpl.has_value());
  EXPECT_NEAR(*lower.cpl, 500.0 / (3.0 * std::sqrt(20000.0)), 1e-9);
}

// First-pass yield counts a unit's first session with its sequence only: a retest that passes
// raises the yield, not the first-pass yield.
TEST(ParameterStats, FirstPassYieldLeavesRetestsOut) {
  std::vector<ParameterSample> samples = {
      Sample("2026-11-02", 1.0, "FAIL", 0.0, 2.0), Sample("2026-11-03", 1.0, "PASS", 0.0, 2.0),
      Sample("2026-11-04", 1.0, "PASS", 0.0, 2.0), Sample("2026-11-05", 1.0, "FAIL", 0.0, 2.0)};
  samples[1].attempt = 2;  // the retest of the first, passed
  const ParameterStats st = ComputeParameterStats("q", samples);
  EXPECT_EQ(st.judged, 4u);
  EXPECT_EQ(st.passed, 2u);
  EXPECT_EQ(st.first_pass_judged, 3u);
  EXPECT_EQ(st.first_pass_passed, 1u);
  ASSERT_TRUE(st.first_pass_yield.has_value());
  EXPECT_DOUBLE_EQ(*st.first_pass_yield, 1.0 / 3.0);
}

TEST(ParameterStats, GroupsSplitBySequenceLimitsAndProduct) {
  std::vector<ParameterSample> samples(4);
  samples[0].sequence_name = "production", samples[0].product = "A";
  samples[1].sequence_name = "paper", samples[1].product = "A";
  samples[2].sequence_name = "production", samples[2].product = "B";
  samples[3].sequence_name = "production", samples[3].product = "A";
  const auto by_sequence = GroupSamples(samples, {GroupBy::kSequence});
  ASSERT_EQ(by_sequence.size(), 2u);
  EXPECT_EQ(by_sequence[0].key, std::vector<std::string>{"paper"});
  EXPECT_EQ(by_sequence[1].samples.size(), 3u);
  const auto both = GroupSamples(samples, {GroupBy::kSequence, GroupBy::kProduct});
  ASSERT_EQ(both.size(), 3u);
  EXPECT_EQ(both[1].key, (std::vector<std::string>{"production", "A"}));
  EXPECT_EQ(both[1].samples.size(), 2u);
  EXPECT_EQ(GroupSamples(samples, {}).size(), 1u);
  EXPECT_FALSE(ParseGroupBy("station").has_value());
}

TEST(ParameterStats, NoSamplesIsNotAnError) {
  const ParameterStats st = ComputeParameterStats("delta1", {});
  EXPECT_EQ(st.n, 0u);
  EXPECT_FALSE(st.yield.has_value());
  EXPECT_TRUE(st.weeks.empty());
}

}  // namespace
