// MinMaxDecimator: long series shown without losing their envelope.
#include "hrgbench/report/decimate.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace hrgbench::report {
namespace {

std::vector<double> Times(std::size_t n) {
  std::vector<double> t(n);
  for (std::size_t k = 0; k < n; ++k) t[k] = 1e-3 * static_cast<double>(k);
  return t;
}

TEST(MinMaxDecimator, ShortSeriesAreKeptWhole) {
  const std::vector<double> t = Times(1500);
  std::vector<double> y(t.size());
  for (std::size_t k = 0; k < y.size(); ++k) y[k] = std::sin(static_cast<double>(k));
  const MinMaxDecimator d(t, 2000);
  EXPECT_FALSE(d.Decimated());
  EXPECT_EQ(d.Times(), t);
  EXPECT_EQ(d.Apply(y.data(), 1), y);
}

// A single-sample spike of a 100 000-sample run (1 kHz, 100 s) is on the page: taking every 50th
// sample would keep it only if it fell on a multiple of 50 (it does not here).
TEST(MinMaxDecimator, ASpikeSurvives) {
  const std::vector<double> t = Times(100'000);
  std::vector<double> y(t.size());
  for (std::size_t k = 0; k < y.size(); ++k) y[k] = 1e-4 * std::sin(0.01 * static_cast<double>(k));
  const std::size_t spike_at = 61'237;
  y[spike_at] = 0.5;
  y[spike_at + 10'001] = -0.25;  // and one downwards
  const MinMaxDecimator d(t, 2000);
  ASSERT_TRUE(d.Decimated());
  EXPECT_LE(d.Times().size(), 2000u);
  const std::vector<double> shown = d.Apply(y.data(), 1);
  ASSERT_EQ(shown.size(), d.Times().size());
  EXPECT_EQ(*std::max_element(shown.begin(), shown.end()), 0.5);
  EXPECT_EQ(*std::min_element(shown.begin(), shown.end()), -0.25);
  // ... at the right time, within one bucket (100 000 / 1000 samples = 0.1 s).
  const std::size_t at = static_cast<std::size_t>(
      std::max_element(shown.begin(), shown.end()) - shown.begin());
  EXPECT_NEAR(d.Times()[at], t[spike_at], 0.1);
  // Every-k-th-sample decimation loses it: the test above can tell the two apart.
  double strided_max = -1.0;
  for (std::size_t k = 0; k < y.size(); k += 50) strided_max = std::max(strided_max, y[k]);
  EXPECT_LT(strided_max, 1e-3);
}

// The envelope: per bucket the shown pair is the bucket's own min and max, in time order.
TEST(MinMaxDecimator, KeepsEachBucketsExtremesInOrder) {
  const std::vector<double> t = Times(10'000);
  std::vector<double> y(t.size());
  for (std::size_t k = 0; k < y.size(); ++k) y[k] = std::cos(0.37 * static_cast<double>(k));
  // Interleaved storage (as y1..y4 in a 4×N matrix): channel 2 of 4.
  std::vector<double> interleaved(4 * y.size(), 0.0);
  for (std::size_t k = 0; k < y.size(); ++k) interleaved[4 * k + 2] = y[k];
  const MinMaxDecimator d(t, 100);
  const std::vector<double> shown = d.Apply(interleaved.data() + 2, 4);
  ASSERT_EQ(shown.size(), 100u);  // 50 buckets of 200 samples
  for (std::size_t b = 0; b < 50; ++b) {
    const auto first = y.begin() + static_cast<std::ptrdiff_t>(200 * b);
    const auto last = first + 200;
    const auto lo = std::min_element(first, last), hi = std::max_element(first, last);
    const bool min_first = lo < hi;
    EXPECT_EQ(shown[2 * b], min_first ? *lo : *hi);
    EXPECT_EQ(shown[2 * b + 1], min_first ? *hi : *lo);
    EXPECT_EQ(d.Times()[2 * b], t[200 * b]);
    EXPECT_EQ(d.Times()[2 * b + 1], t[200 * b + 199]);
  }
}

TEST(MinMaxDecimator, NanSamplesAreSkipped) {
  const std::vector<double> t = Times(1000);
  std::vector<double> y(t.size(), 1.0);
  for (std::size_t k = 0; k < 100; ++k) y[k] = std::nan("");  // bucket 0 entirely NaN
  y[150] = std::nan("");
  y[151] = 3.0;
  const MinMaxDecimator d(t, 20);
  const std::vector<double> shown = d.Apply(y.data(), 1);
  EXPECT_TRUE(std::isnan(shown[0]) && std::isnan(shown[1]));
  EXPECT_EQ(shown[2], 1.0);
  EXPECT_EQ(shown[3], 3.0);
}

}  // namespace
}  // namespace hrgbench::report
