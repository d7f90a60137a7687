// The residual figures' statistics (src/report/residual_statistics.hpp) on data whose answer is
// known: seeded white Gaussian noise (std::mt19937, seed 26; σ and fs below) and a pure tone.
#include "residual_statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace hrgbench::report::internal {
namespace {

std::vector<double> WhiteNoise(std::size_t n, double sigma) {
  std::mt19937 engine(26);
  std::normal_distribution<double> normal(0.0, sigma);
  std::vector<double> out(n);
  for (double& v : out) v = normal(engine);
  return out;
}

TEST(WelchSpectrum, WhiteNoiseReadsTwoSigmaSquaredOverFs) {
  const double sigma = 2.0, fs = 1000.0;
  const std::vector<double> x = WhiteNoise(100000, sigma);
  const PowerSpectrum s = WelchSpectrum(x.data(), 1, x.size(), fs);
  ASSERT_EQ(s.segment_length, 512u);
  EXPECT_EQ(s.segments, (100000 - 512) / 256 + 1);
  ASSERT_EQ(s.frequency_hz.size(), 257u);
  EXPECT_DOUBLE_EQ(s.frequency_hz.back(), fs / 2);
  double mean = 0.0;
  for (std::size_t k = 1; k + 1 < s.density.size(); ++k) mean += s.density[k];
  mean /= static_cast<double>(s.density.size() - 2);
  EXPECT_NEAR(mean / (2 * sigma * sigma / fs), 1.0, 0.02);
}

TEST(WelchSpectrum, ATonePeaksAtItsFrequencyWithItsPower) {
  const double fs = 1000.0, f = 125.0, amplitude = 0.5;
  std::vector<double> x(4096);
  for (std::size_t k = 0; k < x.size(); ++k)
    x[k] = amplitude * std::sin(2 * std::numbers::pi * f * static_cast<double>(k) / fs);
  const PowerSpectrum s = WelchSpectrum(x.data(), 1, x.size(), fs, 256);
  ASSERT_EQ(s.segment_length, 256u);
  std::size_t peak = 0;
  double power = 0.0;  // the density integrated over frequency: the tone's power A²/2
  for (std::size_t k = 0; k < s.density.size(); ++k) {
    if (s.density[k] > s.density[peak]) peak = k;
    power += s.density[k] * fs / 256;
  }
  EXPECT_DOUBLE_EQ(s.frequency_hz[peak], f);
  EXPECT_NEAR(power, amplitude * amplitude / 2, 1e-3);
}

TEST(WelchSpectrum, AStrideReadsOneChannelOfInterleavedSamples) {
  std::vector<double> interleaved(2 * 64, 0.0);
  for (std::size_t k = 0; k < 64; ++k) interleaved[2 * k + 1] = (k % 2 == 0) ? 1.0 : -1.0;
  const PowerSpectrum zero = WelchSpectrum(interleaved.data(), 2, 64, 10.0);
  const PowerSpectrum nyquist = WelchSpectrum(interleaved.data() + 1, 2, 64, 10.0);
  ASSERT_FALSE(zero.density.empty());
  EXPECT_EQ(zero.density.back(), 0.0);
  EXPECT_GT(nyquist.density.back(), 0.0);  // the alternating channel is all at fs/2
  EXPECT_TRUE(WelchSpectrum(interleaved.data(), 1, 7, 10.0).density.empty());
  EXPECT_TRUE(WelchSpectrum(interleaved.data(), 1, 64, 0.0).density.empty());
}

TEST(HistogramOf, GaussianSamplesFollowTheNormalDensity) {
  const double sigma = 1e-4;
  const std::vector<double> x = WhiteNoise(200000, sigma);
  const DensityHistogram h = HistogramOf(x, 5 * sigma, 50);
  ASSERT_EQ(h.edges.size(), 51u);
  ASSERT_EQ(h.density.size(), 50u);
  EXPECT_EQ(h.total, x.size());
  EXPECT_LT(h.outside, 5u);  // beyond 5σ: 0.6 expected
  const double width = 10 * sigma / 50;
  double area = 0.0;
  for (const double d : h.density) area += d * width;
  EXPECT_NEAR(area, 1.0 - static_cast<double>(h.outside) / static_cast<double>(h.total), 1e-12);
  // The two central bins ([−0.2σ, 0] and [0, 0.2σ]) against the normal density there.
  const double central = 0.5 * (h.density[24] + h.density[25]);
  const double expected = (std::erf(0.2 / std::sqrt(2.0)) / 2) / (0.2 * sigma);
  EXPECT_NEAR(central / expected, 1.0, 0.03);
}

TEST(HistogramOf, OutsideAndNotFiniteAreCountedNotBinned) {
  const std::vector<double> x = {0.0, 0.5, 2.0, -3.0, std::nan("")};
  const DensityHistogram h = HistogramOf(x, 1.0, 4);
  EXPECT_EQ(h.total, 4u);
  EXPECT_EQ(h.outside, 2u);
  EXPECT_TRUE(HistogramOf(x, 0.0, 4).density.empty());
}

}  // namespace
}  // namespace hrgbench::report::internal
