// The declared noise shape (estimator/noise_shape.hpp) and the fit's checks under it.
//
// Independent references: a first-order Butterworth sampled at f_s is exactly an AR(1) process
// with ρ = e^{−2π·f_c/f_s} (the sampled exponential autocorrelation), generated here by
// tests/support/out_of_model.hpp's AddNoise; the 4th-order shape is checked against a numerical
// integration of |H|² (not the residues the library uses); the standard error of the residual
// ratio and the whiteness null are checked by their scatter over many noise segments, not by the
// formulas that produced them. The carrier chain's own filter (biquads at the converter rate) is
// compared in tests/unit/sim/carrier_noise_shape_test.cpp.
#include "hrgbench/estimator/noise_shape.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "hrgbench/estimator/fit_diagnostics.hpp"
#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "out_of_model.hpp"

namespace hrgbench::estimator {
namespace {

constexpr double kPi = std::numbers::pi;

// Four channels of AR(1) noise (std sigma, lag-1 correlation rho), `n` samples.
Eigen::Matrix4Xd Ar1Noise(Eigen::Index n, double sigma, double rho, std::uint64_t seed) {
  RunData run;
  run.t_s.resize(static_cast<std::size_t>(n));
  run.y = Eigen::Matrix4Xd::Zero(4, n);
  testing::AddNoise(&run, sigma, rho, seed);
  return run.y;
}

double MeanOf(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x;
  return sum / static_cast<double>(v.size());
}

double StdOf(const std::vector<double>& v) {
  const double mean = MeanOf(v);
  double sum = 0.0;
  for (double x : v) sum += (x - mean) * (x - mean);
  return std::sqrt(sum / static_cast<double>(v.size() - 1));
}

TEST(NoiseShapeTest, WhiteGivesExactlyTheWhiteNoiseChecks) {
  const NoiseShape white;
  EXPECT_TRUE(white.IsWhite());
  const DifferenceNoiseModel d = DifferenceNoiseModelFor(white);
  EXPECT_EQ(d.stride, 1);
  EXPECT_DOUBLE_EQ(d.variance_factor, 70.0);
  // docs/estimator/methods.md's derivation of the white-noise standard error: 0.451.
  EXPECT_NEAR(d.ratio_standard_error_scale, kResidualRatioStandardErrorScale, 5e-4);
  const WhitenessNull null = WhitenessNullFor(white, 20);
  EXPECT_EQ(null.first_lag, 1);
  EXPECT_EQ(null.lags, 20);
  EXPECT_DOUBLE_EQ(null.scale, 1.0);
  EXPECT_DOUBLE_EQ(null.dof, 80.0);
}

TEST(NoiseShapeTest, FirstOrderButterworthIsTheSampledExponential) {
  const double cutoff_hz = 100.0, rate_hz = 1000.0;
  const auto shape = ButterworthNoiseShape(1, cutoff_hz, rate_hz);
  ASSERT_TRUE(shape);
  EXPECT_TRUE(shape->IsValid(nullptr));
  // Declared to where it falls below 1e-9 (lag 33: e^{−0.628·33} = 9.9e-10), zero beyond.
  for (int k = 0; k <= 40; ++k)
    EXPECT_NEAR(shape->Rho(k), std::exp(-2.0 * kPi * cutoff_hz * k / rate_hz), 1e-9) << k;
  EXPECT_EQ(shape->autocorrelation.size(), 33u);
  EXPECT_NEAR(shape->Rho(32), std::exp(-2.0 * kPi * cutoff_hz * 32 / rate_hz), 1e-15);
  EXPECT_EQ(shape->Rho(-3), shape->Rho(3));
}

TEST(NoiseShapeTest, FourthOrderButterworthMatchesTheIntegralOfItsPowerResponse) {
  const double cutoff_hz = 200.0, rate_hz = 1000.0;
  const auto shape = ButterworthNoiseShape(4, cutoff_hz, rate_hz);
  ASSERT_TRUE(shape);
  // R(τ) = ∫_0^∞ cos(2πfτ)/(1 + (f/f_c)^8) df by Simpson's rule on [0, 100·f_c] (the tail beyond
  // is below 1e-14 of R(0)), in units of f_c.
  const auto r = [](double tau_cutoffs) {
    const int n = 400000;
    const double h = 100.0 / n;
    double sum = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double f = i * h;
      const double w = (i == 0 || i == n) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
      sum += w * std::cos(2.0 * kPi * f * tau_cutoffs) / (1.0 + std::pow(f, 8));
    }
    return sum * h / 3.0;
  };
  const double r0 = r(0.0);
  for (int k = 1; k <= 12; ++k)
    EXPECT_NEAR(shape->Rho(k), r(k * cutoff_hz / rate_hz) / r0, 1e-8) << k;
  // Its memory: the lag from which |ρ| stays at or below 0.01.
  const int memory = NoiseMemoryLags(*shape);
  EXPECT_GT(memory, 1);
  for (int k = memory; k < memory + 50; ++k) EXPECT_LE(std::abs(shape->Rho(k)), 0.01) << k;
  EXPECT_GT(std::abs(shape->Rho(memory - 1)), 0.01);
}

TEST(NoiseShapeTest, RefusesWhatItCannotRepresent) {
  EXPECT_FALSE(ButterworthNoiseShape(0, 200.0, 1000.0));
  EXPECT_FALSE(ButterworthNoiseShape(13, 200.0, 1000.0));
  EXPECT_FALSE(ButterworthNoiseShape(4, -1.0, 1000.0));
  // A 0.01 Hz cutoff at 1 kHz remembers for ~10^5 samples: refused, not truncated.
  EXPECT_FALSE(ButterworthNoiseShape(4, 0.01, 1000.0));
  NoiseShape bad;
  bad.autocorrelation = {1.0, 1.5};
  EXPECT_FALSE(bad.IsValid(nullptr));
  bad.autocorrelation = {0.5};
  EXPECT_FALSE(bad.IsValid(nullptr));
}

// The noise σ from 4th differences: right under the declared shape, far too small when the
// colour is ignored (the finding on the carrier chain: residual ratio ≈ 5.7).
TEST(NoiseShapeTest, DifferenceNoiseSigmaIsRightUnderTheDeclaredShape) {
  const double sigma = 1e-4, cutoff_hz = 50.0, rate_hz = 1000.0;
  const double rho = std::exp(-2.0 * kPi * cutoff_hz / rate_hz);  // 0.73
  const Eigen::Matrix4Xd y = Ar1Noise(200000, sigma, rho, 7);
  const auto shape = ButterworthNoiseShape(1, cutoff_hz, rate_hz);
  ASSERT_TRUE(shape);
  const DifferenceNoiseModel model = DifferenceNoiseModelFor(*shape);
  EXPECT_GT(model.stride, 1);
  EXPECT_NEAR(model.variance_factor, 70.0, 0.02 * 70.0);
  // Relative standard error of σ̂ over 8e5 values with the differences' correlation: < 0.3 %.
  EXPECT_NEAR(DifferenceNoiseSigma(y, model), sigma, 0.01 * sigma);
  EXPECT_LT(DifferenceNoiseSigma(y), 0.6 * sigma);
}

// The residual ratio's standard error under the shape (derived in noise_shape.hpp) against its
// scatter over 1500 segments of pure noise (residuals = noise: a fit removes a negligible share).
TEST(NoiseShapeTest, ResidualRatioStandardErrorMatchesItsScatter) {
  for (const double cutoff_hz : {0.0, 50.0, 150.0}) {
    const double rate_hz = 1000.0;
    NoiseShape shape;
    double rho = 0.0;
    if (cutoff_hz > 0.0) {
      shape = *ButterworthNoiseShape(1, cutoff_hz, rate_hz);
      rho = std::exp(-2.0 * kPi * cutoff_hz / rate_hz);
    }
    const DifferenceNoiseModel model = DifferenceNoiseModelFor(shape);
    const Eigen::Index n = 1000;
    std::vector<double> ratios;
    for (int i = 0; i < 1500; ++i) {
      const Eigen::Matrix4Xd noise = Ar1Noise(n, 1.0, rho, 1000 + i);
      const double rms = std::sqrt(noise.squaredNorm() / (4.0 * n));
      ratios.push_back(rms / DifferenceNoiseSigma(noise, model));
    }
    // The scatter of a std over 1500 values is known to ±1.8 %; the derivation's first-order
    // expansion and the trimming add a little: ±12 %.
    const double expected = model.ratio_standard_error_scale / std::sqrt(static_cast<double>(n));
    EXPECT_NEAR(StdOf(ratios), expected, 0.12 * expected) << "cutoff " << cutoff_hz;
    EXPECT_NEAR(MeanOf(ratios), 1.0, 4.0 * expected) << "cutoff " << cutoff_hz;
  }
}

// Under the declared shape the whiteness score of pure noise is ≈ N(0, 1); under the white null
// the same noise reads as grossly coloured.
TEST(NoiseShapeTest, WhitenessScoreOfShapedNoiseIsStandardNormal) {
  const double cutoff_hz = 50.0, rate_hz = 1000.0;
  const double rho = std::exp(-2.0 * kPi * cutoff_hz / rate_hz);
  const NoiseShape shape = *ButterworthNoiseShape(1, cutoff_hz, rate_hz);
  const WhitenessNull null = WhitenessNullFor(shape, 20);
  EXPECT_GT(null.first_lag, 1);
  EXPECT_GT(null.scale, 1.0);  // the lags' autocorrelations scatter more than white noise's
  std::vector<double> z, z_white;
  for (int i = 0; i < 600; ++i) {
    const Eigen::Matrix4Xd noise = Ar1Noise(4000, 1.0, rho, 5000 + i);
    z.push_back(AnalyseResiduals(noise, null).ljung_box_z);
    if (i < 20) z_white.push_back(AnalyseResiduals(noise, 20).ljung_box_z);
  }
  // Mean known to ±0.04, std to ±3 % over 600 segments; the Satterthwaite and Wilson–Hilferty
  // approximations: ±0.2 and ±20 %.
  EXPECT_NEAR(MeanOf(z), 0.0, 0.2);
  EXPECT_NEAR(StdOf(z), 1.0, 0.2);
  double largest = 0.0;
  for (double v : z) largest = std::max(largest, v);
  EXPECT_LT(largest, 6.0);  // the default limit: no false alarm
  // ρ = 0.73 at lag 1 over 4000 samples: Q ≈ 4·4000·Σρ^{2k} ≈ 1.8e4 against χ²(80), z ≈ 97
  // (Wilson–Hilferty), far beyond the limit of 6.
  for (double v : z_white) EXPECT_GT(v, 50.0);
}

// The fit: a production session with noise of the declared shape passes its checks with the
// sandwich covariance; declared white it fails them; and colour beyond the declaration (an AR(1)
// with ρ = 0.9 added, the row) is flagged even with the declaration.
TEST(NoiseShapeTest, FitJudgesTheResidualsAgainstTheDeclaredShape) {
  const double sigma = 1e-4, cutoff_hz = 50.0, rate_hz = 500.0;
  const double rho = std::exp(-2.0 * kPi * cutoff_hz / rate_hz);  // 0.53
  SimulationOptions truth = testing::ProductionTruth();
  truth.sigma = 0.0;
  const std::vector<RunData> clean = SimulateRuns(testing::ProductionPlans(4.0, rate_hz), truth);
  ASSERT_FALSE(clean.empty());
  std::vector<RunData> shaped = clean, beyond = clean;
  for (std::size_t r = 0; r < clean.size(); ++r) {
    testing::AddNoise(&shaped[r], sigma, rho, 300 + r);
    testing::AddNoise(&beyond[r], sigma, rho, 300 + r);
    testing::AddNoise(&beyond[r], sigma, 0.9, 700 + r);
  }
  MlOptions declared;
  declared.noise_shape = *ButterworthNoiseShape(1, cutoff_hz, rate_hz);

  const EstimateSummary good = EstimateMaximumLikelihood(shaped, declared);
  ASSERT_TRUE(good.IsUsable()) << good.message;
  EXPECT_TRUE(good.diagnostics.Acceptable())
      << (good.diagnostics.problems.empty() ? "" : good.diagnostics.problems.front());
  EXPECT_EQ(good.diagnostics.covariance_kind, "sandwich");
  EXPECT_EQ(good.diagnostics.noise_shape, declared.noise_shape.description);
  for (const std::string& w : good.warnings)
    EXPECT_EQ(w.find("not white"), std::string::npos) << w;  // declared colour is no warning
  for (const RunFitDiagnostics& run : good.diagnostics.runs)
    EXPECT_NEAR(run.noise_sigma, sigma, 0.05 * sigma);

  const EstimateSummary white = EstimateMaximumLikelihood(shaped, MlOptions{});
  ASSERT_TRUE(white.IsUsable());
  EXPECT_FALSE(white.diagnostics.Acceptable());

  const EstimateSummary coloured = EstimateMaximumLikelihood(beyond, declared);
  ASSERT_TRUE(coloured.IsUsable());
  ASSERT_FALSE(coloured.diagnostics.Acceptable());
  bool names_the_declaration = false;
  for (const std::string& p : coloured.diagnostics.problems)
    names_the_declaration = names_the_declaration || p.find("declare") != std::string::npos;
  EXPECT_TRUE(names_the_declaration) << coloured.diagnostics.problems.front();
}

}  // namespace
}  // namespace hrgbench::estimator
