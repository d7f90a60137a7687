// The rate error's harmonics against a rate error made in the test from known coefficients: a bias
// and two harmonics of 2θ, plus white noise of a known std per sample, over whole turns. The fit
// must find each coefficient within 4 of its stated std, and the stated std must be the scatter's:
// for N windows evenly spread over whole turns the least-squares std of the bias is σ_w/√N and of
// each harmonic coefficient σ_w·√(2/N), σ_w = σ/√window (white noise averaged in a window).

#include "hrgbench/analysis/rate_error_harmonics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace hrgbench::analysis {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(RateErrorHarmonicsTest, FindsTheCoefficientsWithTheStdTheScatterHas) {
  const double bias = 2e-6, c1 = 3e-5, s1 = -1e-5, c2 = 4e-6, s2 = 0.0, sigma = 1e-4;
  const std::size_t n = 200000, window = 100;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<double> angle(n), error(n);
  for (std::size_t k = 0; k < n; ++k) {
    angle[k] = 0.2 - 2.0 * kPi * static_cast<double>(k) / static_cast<double>(n);  // 2θ: 2 turns
    const double t = 2.0 * angle[k];
    error[k] = bias + c1 * std::cos(t) + s1 * std::sin(t) + c2 * std::cos(2 * t) +
               s2 * std::sin(2 * t) + noise(rng);
  }
  const auto fit = FitRateErrorHarmonics(angle, error, window, 2);
  ASSERT_TRUE(fit.ok) << fit.why;
  EXPECT_EQ(fit.windows, n / window);
  const double windows = static_cast<double>(fit.windows);
  const double sigma_w = sigma / std::sqrt(static_cast<double>(window));
  EXPECT_NEAR(fit.bias_std_rad_s, sigma_w / std::sqrt(windows), 0.1 * sigma_w / std::sqrt(windows));
  EXPECT_NEAR(fit.cos_std_rad_s[0], sigma_w * std::sqrt(2.0 / windows),
              0.1 * sigma_w * std::sqrt(2.0 / windows));
  EXPECT_NEAR(fit.bias_rad_s, bias, 4.0 * fit.bias_std_rad_s);
  EXPECT_NEAR(fit.cos_rad_s[0], c1, 4.0 * fit.cos_std_rad_s[0]);
  EXPECT_NEAR(fit.sin_rad_s[0], s1, 4.0 * fit.sin_std_rad_s[0]);
  EXPECT_NEAR(fit.cos_rad_s[1], c2, 4.0 * fit.cos_std_rad_s[1]);
  EXPECT_NEAR(fit.sin_rad_s[1], s2, 4.0 * fit.sin_std_rad_s[1]);
  EXPECT_NEAR(fit.angle_dependent_rms_rad_s,
              std::sqrt((c1 * c1 + s1 * s1 + c2 * c2 + s2 * s2) / 2.0), 1e-6);
  EXPECT_NEAR(fit.residual_rms_rad_s, sigma_w, 0.05 * sigma_w);
  EXPECT_NEAR(fit.angle_span_rad, 4.0 * kPi, 0.01);
}

TEST(RateErrorHarmonicsTest, RefusesWhatCannotBeFittedAndSaysWhy) {
  const std::vector<double> angle(1000, 0.3), error(1000, 1e-6);
  auto fit = FitRateErrorHarmonics(angle, error, 10, 1);
  EXPECT_FALSE(fit.ok);
  EXPECT_NE(fit.why.find("did not turn"), std::string::npos) << fit.why;
  fit = FitRateErrorHarmonics(angle, std::vector<double>(999, 0.0), 10, 1);
  EXPECT_FALSE(fit.ok);
  EXPECT_NE(fit.why.find("lengths"), std::string::npos) << fit.why;
  fit = FitRateErrorHarmonics(angle, error, 0, 1);
  EXPECT_FALSE(fit.ok);
  fit = FitRateErrorHarmonics(angle, error, 200, 2);  // 5 windows for 5 coefficients
  EXPECT_FALSE(fit.ok);
  EXPECT_NE(fit.why.find("too few"), std::string::npos) << fit.why;
  std::vector<double> turning(1000), with_nan(1000, 0.0);
  for (std::size_t k = 0; k < turning.size(); ++k) turning[k] = 0.01 * static_cast<double>(k);
  with_nan[500] = std::nan("");
  fit = FitRateErrorHarmonics(turning, with_nan, 10, 1);
  EXPECT_FALSE(fit.ok);
  EXPECT_NE(fit.why.find("not finite"), std::string::npos) << fit.why;
}

}  // namespace
}  // namespace hrgbench::analysis
