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
  EXPECT_FALSE(st.cp.has_value());
  ASSERT_TRUE(st.cpk.has_value());
  EXPECT_DOUBLE_EQ(*st.cpk, (5.0 - 2.0) / 3.0);
  EXPECT_EQ(st.judged, 2u);  // the third had no verdict on q
  EXPECT_DOUBLE_EQ(*st.yield, 1.0);
  ASSERT_EQ(st.weeks.size(), 1u);
  EXPECT_EQ(st.weeks[0].week, "2026-W45");
}

TEST(ParameterStats, NoSamplesIsNotAnError) {
  const ParameterStats st = ComputeParameterStats("delta1", {});
  EXPECT_EQ(st.n, 0u);
  EXPECT_FALSE(st.yield.has_value());
  EXPECT_TRUE(st.weeks.empty());
}

}  // namespace
