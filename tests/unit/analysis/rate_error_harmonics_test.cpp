// The rate error's harmonics against a rate error made in the test from known coefficients (a bias
// and two harmonics of 2θ over two whole turns) plus one of the two noises the fit is told about:
//   - white angle noise of std σ_θ on each sample's angle (the pick-off's): the rate of sample k is
//     (n_k − n_{k−1})/h on top of the error;
//   - white rate noise of std σ on each sample's rate (angle random walk).
// For each, over 300 records: every coefficient's mean within 4 standard errors of the truth, and
// the std the fit states equal to the coefficients' scatter over the records within 15 % (the
// scatter's own sampling error is 4 % at 300 records).

#include "hrgbench/analysis/rate_error_harmonics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace hrgbench::analysis {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kH = 1e-3;
constexpr double kBias = 2e-6, kC1 = 3e-5, kS1 = -1e-5, kC2 = 4e-6, kS2 = 0.0;

struct Record {
  std::vector<double> angle, error;
};

Record Make(std::size_t n, RateErrorNoise noise, double sigma, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, sigma);
  Record r{std::vector<double>(n), std::vector<double>(n)};
  double previous_angle_noise = normal(rng);
  for (std::size_t k = 0; k < n; ++k) {
    r.angle[k] = 0.2 - 2.0 * kPi * static_cast<double>(k) / static_cast<double>(n);  // 2θ: 2 turns
    const double t = 2.0 * r.angle[k];
    r.error[k] = kBias + kC1 * std::cos(t) + kS1 * std::sin(t) + kC2 * std::cos(2 * t) +
                 kS2 * std::sin(2 * t);
    if (noise == RateErrorNoise::kWhiteRate) {
      r.error[k] += normal(rng);
    } else {
      const double angle_noise = normal(rng);
      r.error[k] += (angle_noise - previous_angle_noise) / kH;
      previous_angle_noise = angle_noise;
    }
  }
  return r;
}

void CheckAgainstScatter(RateErrorNoise noise, double sigma) {
  std::mt19937_64 rng(7);
  const int records = 300;
  const std::size_t n = 20000, window = 50;
  const double truth[5] = {kBias, kC1, kS1, kC2, kS2};
  double sum[5] = {}, sum_squares[5] = {}, stated[5] = {};
  for (int r = 0; r < records; ++r) {
    const Record record = Make(n, noise, sigma, rng);
    const auto fit = FitRateErrorHarmonics(record.angle, record.error, kH, window, 2, noise);
    ASSERT_TRUE(fit.ok) << fit.why;
    const double value[5] = {fit.bias_rad_s, fit.cos_rad_s[0], fit.sin_rad_s[0], fit.cos_rad_s[1],
                             fit.sin_rad_s[1]};
    const double std[5] = {fit.bias_std_rad_s, fit.cos_std_rad_s[0], fit.sin_std_rad_s[0],
                           fit.cos_std_rad_s[1], fit.sin_std_rad_s[1]};
    for (int i = 0; i < 5; ++i) {
      sum[i] += value[i];
      sum_squares[i] += (value[i] - truth[i]) * (value[i] - truth[i]);
      stated[i] += std[i] / records;
    }
  }
  const char* names[5] = {"bias", "c1", "s1", "c2", "s2"};
  for (int i = 0; i < 5; ++i) {
    const double scatter = std::sqrt(sum_squares[i] / records);
    EXPECT_NEAR(sum[i] / records, truth[i], 4.0 * scatter / std::sqrt(records)) << names[i];
    EXPECT_NEAR(stated[i], scatter, 0.15 * scatter) << names[i];
  }
}

TEST(RateErrorHarmonicsTest, UnderThePickoffsAngleNoiseTheStatedStdIsTheScatter) {
  CheckAgainstScatter(RateErrorNoise::kWhiteAngle, 1e-4);
}

TEST(RateErrorHarmonicsTest, UnderAngleRandomWalkTheStatedStdIsTheScatter) {
  CheckAgainstScatter(RateErrorNoise::kWhiteRate, 1e-3);
}

TEST(RateErrorHarmonicsTest, FindsNoiseFreeCoefficientsExactly) {
  std::mt19937_64 rng(1);
  const Record record = Make(20000, RateErrorNoise::kWhiteRate, 0.0, rng);
  for (const auto noise : {RateErrorNoise::kWhiteAngle, RateErrorNoise::kWhiteRate}) {
    const auto fit = FitRateErrorHarmonics(record.angle, record.error, kH, 50, 2, noise);
    ASSERT_TRUE(fit.ok) << fit.why;
    // Windows average the harmonics over 50 samples of a turn of 10 000: a sinc of 1 − 3e-5.
    EXPECT_NEAR(fit.bias_rad_s, kBias, 1e-10);
    EXPECT_NEAR(fit.cos_rad_s[0], kC1, 1e-4 * kC1);
    EXPECT_NEAR(fit.sin_rad_s[0], kS1, 1e-4 * kC1);
    EXPECT_NEAR(fit.cos_rad_s[1], kC2, 1e-4 * kC1);
    EXPECT_NEAR(fit.angle_dependent_rms_rad_s, std::sqrt((kC1 * kC1 + kS1 * kS1 + kC2 * kC2) / 2.0),
                1e-4 * kC1);
    // From the first window's mean angle to the last's: 399 of the 400 windows' turn.
    EXPECT_NEAR(fit.angle_span_rad, 4.0 * kPi * 399.0 / 400.0, 1e-9);
    EXPECT_EQ(fit.windows, 400u);
  }
}

TEST(RateErrorHarmonicsTest, RefusesWhatCannotBeFittedAndSaysWhy) {
  const std::vector<double> angle(1000, 0.3), error(1000, 1e-6);
  for (const auto noise : {RateErrorNoise::kWhiteAngle, RateErrorNoise::kWhiteRate}) {
    auto fit = FitRateErrorHarmonics(angle, error, kH, 10, 1, noise);
    EXPECT_FALSE(fit.ok);
    EXPECT_NE(fit.why.find("did not turn"), std::string::npos) << fit.why;
  }
  auto fit = FitRateErrorHarmonics(angle, std::vector<double>(999, 0.0), kH, 10, 1);
  EXPECT_FALSE(fit.ok);
  EXPECT_NE(fit.why.find("lengths"), std::string::npos) << fit.why;
  EXPECT_FALSE(FitRateErrorHarmonics(angle, error, kH, 0, 1).ok);
  EXPECT_FALSE(FitRateErrorHarmonics(angle, error, 0.0, 10, 1).ok);
  fit = FitRateErrorHarmonics(angle, error, kH, 200, 2);  // 5 windows for 6 unknowns
  EXPECT_FALSE(fit.ok);
  EXPECT_NE(fit.why.find("too few"), std::string::npos) << fit.why;
  std::vector<double> turning(1000), with_nan(1000, 0.0);
  for (std::size_t k = 0; k < turning.size(); ++k) turning[k] = 0.01 * static_cast<double>(k);
  with_nan[500] = std::nan("");
  fit = FitRateErrorHarmonics(turning, with_nan, kH, 10, 1);
  EXPECT_FALSE(fit.ok);
  EXPECT_NE(fit.why.find("not finite"), std::string::npos) << fit.why;
}

}  // namespace
}  // namespace hrgbench::analysis
