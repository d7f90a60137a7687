// The scale-factor fit against what the holds were made from: exact lines, a curved response whose
// nonlinearity is known in closed form, and the reported stds against the scatter of many noisy
// verifications (Monte Carlo).

#include "hrgbench/analysis/scale_factor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace hrgbench::analysis {
namespace {

TEST(ScaleFactor, TwoRatesGiveTheLineExactlyAndNoNonlinearity) {
  // Ω̂ = (1 + 250 ppm)·Ω + 1e-5 rad/s, held at ±0.3 rad/s.
  const std::vector<RateHoldMean> holds = {{0.3, 1e-5 + 250e-6 * 0.3, 1e-7},
                                           {-0.3, 1e-5 - 250e-6 * 0.3, 1e-7}};
  const ScaleFactorFit fit = FitScaleFactor(holds);
  ASSERT_TRUE(fit.ok) << fit.why;
  EXPECT_NEAR(fit.scale_factor_error * 1e6, 250.0, 1e-6);
  EXPECT_NEAR(fit.bias_rad_s, 1e-5, 1e-15);
  EXPECT_FALSE(fit.nonlinearity_known);
  EXPECT_EQ(fit.dof, 0);
  // Two points of equal std σ at ±Ω: std(ε) = σ / (Ω√2), std(b) = σ / √2.
  EXPECT_NEAR(fit.scale_factor_error_std, 1e-7 / (0.3 * std::sqrt(2.0)), 1e-15);
  EXPECT_NEAR(fit.bias_std_rad_s, 1e-7 / std::sqrt(2.0), 1e-15);
}

TEST(ScaleFactor, AQuadraticResponseShowsItsNonlinearity) {
  // e = k·Ω² at Ω = −1, 0, 1 (equal weights): the line is e = 2k/3, slope 0; residuals k/3,
  // −2k/3, k/3; the largest, 2k/3, over full scale 1.
  const double k = 3e-6;
  const std::vector<RateHoldMean> holds = {{-1.0, k, 1e-6}, {0.0, 0.0, 1e-6}, {1.0, k, 1e-6}};
  const ScaleFactorFit fit = FitScaleFactor(holds);
  ASSERT_TRUE(fit.ok) << fit.why;
  EXPECT_NEAR(fit.scale_factor_error, 0.0, 1e-15);
  EXPECT_NEAR(fit.bias_rad_s, 2.0 * k / 3.0, 1e-15);
  ASSERT_TRUE(fit.nonlinearity_known);
  EXPECT_NEAR(fit.nonlinearity, 2.0 * k / 3.0, 1e-15);
  // χ² = (1 + 4 + 1)·(k/3)²/σ² = 6 on one degree of freedom: the stds scaled by √6.
  EXPECT_NEAR(fit.chi2, 6.0, 1e-9);
  EXPECT_EQ(fit.dof, 1);
  EXPECT_NEAR(fit.bias_std_rad_s, std::sqrt(6.0) * 1e-6 / std::sqrt(3.0), 1e-12);
}

TEST(ScaleFactor, ReportedStdsMatchTheScatterOfRepeatedVerifications) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  const std::vector<double> rates = {-1.0, -0.3, 0.3, 1.0};
  const std::vector<double> sigmas = {2e-7, 1e-7, 1e-7, 2e-7};
  const double eps = -40e-6, bias = 3e-6;
  const int trials = 4000;
  double sum_e = 0.0, sum_e2 = 0.0, sum_b = 0.0, sum_b2 = 0.0, reported_e = 0.0;
  for (int t = 0; t < trials; ++t) {
    std::vector<RateHoldMean> holds;
    for (std::size_t i = 0; i < rates.size(); ++i)
      holds.push_back({rates[i], bias + eps * rates[i] + sigmas[i] * noise(rng), sigmas[i]});
    const ScaleFactorFit fit = FitScaleFactor(holds);
    ASSERT_TRUE(fit.ok);
    sum_e += fit.scale_factor_error;
    sum_e2 += fit.scale_factor_error * fit.scale_factor_error;
    sum_b += fit.bias_rad_s;
    sum_b2 += fit.bias_rad_s * fit.bias_rad_s;
    // Without the Birge scaling, the std is the information's: the same every trial.
    reported_e = fit.chi2 / fit.dof <= 1.0 ? fit.scale_factor_error_std : reported_e;
  }
  const double mean_e = sum_e / trials, mean_b = sum_b / trials;
  const double sd_e = std::sqrt(sum_e2 / trials - mean_e * mean_e);
  const double sd_b = std::sqrt(sum_b2 / trials - mean_b * mean_b);
  EXPECT_NEAR(mean_e, eps, 4.0 * sd_e / std::sqrt(trials));
  EXPECT_NEAR(mean_b, bias, 4.0 * sd_b / std::sqrt(trials));
  // The information's std of ε: 1/√(Σw·Σwx² − (Σwx)²)·√Σw, by hand for these rates and weights:
  // Σw = 2/4e-14 + 2/1e-14 = 2.5e14, Σwx = 0, Σwx² = 2·1/4e-14 + 2·0.09/1e-14 = 6.8e13.
  const double expected = 1.0 / std::sqrt(6.8e13);
  EXPECT_NEAR(reported_e, expected, 1e-3 * expected);
  EXPECT_NEAR(sd_e, expected, 0.05 * expected);  // 4000 trials: the sd's own std is 1.1 %
}

TEST(ScaleFactor, OneRateOrABadStdIsRefused) {
  EXPECT_FALSE(FitScaleFactor(std::vector<RateHoldMean>{{0.3, 0.0, 1e-7}, {0.3, 0.0, 1e-7}}).ok);
  EXPECT_FALSE(FitScaleFactor(std::vector<RateHoldMean>{{0.3, 0.0, 0.0}, {-0.3, 0.0, 1e-7}}).ok);
  EXPECT_FALSE(FitScaleFactor(std::vector<RateHoldMean>{{0.3, NAN, 1e-7}, {-0.3, 0.0, 1e-7}}).ok);
}

// The asymmetry against a response made with different slopes for each sign: Ω̂ − Ω = b + ε+·Ω for
// Ω > 0 and b + ε−·Ω for Ω < 0 (IEEE 1431's definition, ε+ − ε−, made directly, not through the
// |Ω| parametrisation the fit uses).
TEST(ScaleFactor, SlopesThatDifferBySignShowTheirAsymmetry) {
  const double bias = 2e-6, plus = 30e-6, minus = -15e-6;
  std::vector<RateHoldMean> holds;
  for (const double omega : {-1.0, -0.3, 0.3, 1.0})
    holds.push_back({omega, bias + (omega > 0 ? plus : minus) * omega, 1e-7});
  const ScaleFactorFit fit = FitScaleFactor(holds);
  ASSERT_TRUE(fit.ok) << fit.why;
  ASSERT_TRUE(fit.asymmetry_known);
  EXPECT_NEAR(fit.asymmetry * 1e6, 45.0, 1e-6);
  // Four holds of equal σ at ±0.3, ±1: α's information is Σw·|Ω|² less what b and ε share with
  // it; by hand, with w = 1/σ², the normal matrix for (b, ε, α) is w·[[4, 0, 2.6], [0, 2.18, 0],
  // [2.6, 0, 2.18]], so var(α) = σ²·4/(4·2.18 − 2.6²) and std(2α) = 2σ·√(4/1.96).
  EXPECT_NEAR(fit.asymmetry_std, 2.0 * 1e-7 * std::sqrt(4.0 / 1.96), 1e-12);
  // A symmetric response has none, within its std.
  std::vector<RateHoldMean> symmetric;
  for (const double omega : {-1.0, -0.3, 0.3, 1.0})
    symmetric.push_back({omega, bias + plus * omega, 1e-7});
  const ScaleFactorFit line = FitScaleFactor(symmetric);
  ASSERT_TRUE(line.asymmetry_known);
  EXPECT_NEAR(line.asymmetry, 0.0, 1e-12);
}

TEST(ScaleFactor, TheAsymmetryNeedsBothSignsAndTwoMagnitudes) {
  const auto known = [](std::vector<double> rates) {
    std::vector<RateHoldMean> holds;
    for (const double omega : rates) holds.push_back({omega, 1e-6 * omega, 1e-7});
    return FitScaleFactor(holds).asymmetry_known;
  };
  EXPECT_FALSE(known({0.3, -0.3}));             // α and the bias are the same column
  EXPECT_FALSE(known({0.3, -0.3, 0.3, -0.3}));  // still one magnitude
  EXPECT_FALSE(known({0.3, 1.0, 2.0}));         // one sign
  EXPECT_TRUE(known({0.3, -0.3, 1.0}));
}

}  // namespace
}  // namespace hrgbench::analysis
