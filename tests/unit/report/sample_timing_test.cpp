// The report's sample-timing rows against a direct long-double evaluation of the same steps.
#include "sample_timing.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace hrgbench::report {
namespace {

// The steps' std about their mean, in long double and two passes: the reference.
long double ReferenceStd(const std::vector<double>& t) {
  long double sum = 0.0L;
  for (std::size_t k = 1; k < t.size(); ++k) sum += static_cast<long double>(t[k] - t[k - 1]);
  const long double n = static_cast<long double>(t.size() - 1);
  const long double mean = sum / n;
  long double squares = 0.0L;
  for (std::size_t k = 1; k < t.size(); ++k) {
    const long double d = static_cast<long double>(t[k] - t[k - 1]) - mean;
    squares += d * d;
  }
  return std::sqrt(squares / n);
}

// 1 kHz for 600 s: the steps differ only by the rounding of t (~1e-13 s). The std must be of that
// size and never above the largest deviation; the one-pass formula gave ~1e-11 s here.
TEST(SampleTiming, TheStdOfNearlyEqualStepsIsTheirRoundingNotTheFormulas) {
  std::vector<double> t(600'000);
  for (std::size_t k = 0; k < t.size(); ++k) t[k] = static_cast<double>(k) / 1000.0;
  const SampleTiming timing = MeasureSampleTiming(t, 1000.0);
  const double reference = static_cast<double>(ReferenceStd(t));
  ASSERT_GT(reference, 0.0);
  EXPECT_NEAR(timing.jitter_std_s, reference, 1e-6 * reference);
  EXPECT_LE(timing.jitter_std_s, timing.jitter_max_s);
  EXPECT_LT(timing.jitter_max_s, 1e-12);
  EXPECT_NEAR(timing.interval_s, 1e-3, 1e-15);
  EXPECT_EQ(timing.long_steps, 0u);
}

// Exactly representable steps with one lost sample: one long step, its deviation the maximum.
TEST(SampleTiming, ALostSampleIsOneLongStep) {
  std::vector<double> t;
  for (int k = 0; k < 1000; ++k)
    if (k != 500) t.push_back(0.25 * k);
  const SampleTiming timing = MeasureSampleTiming(t, 4.0);
  EXPECT_EQ(timing.long_steps, 1u);
  EXPECT_DOUBLE_EQ(timing.jitter_max_s, 0.25);
  EXPECT_NEAR(timing.jitter_std_s, static_cast<double>(ReferenceStd(t)), 1e-15);
}

// No recorded rate: the median step is the nominal one.
TEST(SampleTiming, WithoutARateTheMedianStepIsNominal) {
  const std::vector<double> t = {0.0, 0.5, 1.0, 1.5, 2.5, 3.0};
  const SampleTiming timing = MeasureSampleTiming(t, std::nan(""));
  EXPECT_EQ(timing.long_steps, 1u);
  EXPECT_DOUBLE_EQ(timing.jitter_max_s, 0.5);
}

TEST(SampleTiming, FewerThanTwoSamplesMeasureNothing) {
  const SampleTiming timing = MeasureSampleTiming(std::vector<double>{1.0}, 100.0);
  EXPECT_TRUE(std::isnan(timing.jitter_std_s));
  EXPECT_EQ(timing.long_steps, 0u);
}

}  // namespace
}  // namespace hrgbench::report
