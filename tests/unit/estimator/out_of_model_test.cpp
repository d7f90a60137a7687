// Outside its own model the estimator is right, or says that it is not (docs/estimator/methods.md
// "Is the fit right?").
// Each row of the table is a test here: the perturbation is applied to a session simulated
// by the model (tests/support/out_of_model.hpp, written from the perturbations' definitions, not
// with the estimator's propagator), and the default estimator must either stay within its reported
// std of the truth or report a problem naming the run. Each test also fits with the model alone
// (no common phase, Ω exact, no outlier removal, white covariance) to show the perturbation bites:
// a test that cannot fail proves nothing.
//
// Sizes: the production design's six runs, 2–10 s at 500 Hz, σ = 1e-4 (the table in
// docs/measurements/ uses 100 s at 1 kHz); "shift" = (estimate on the perturbed data − estimate on
// the same noise without the perturbation) / reported std, so the noise itself does not enter the
// bound.
#include "out_of_model.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "estimator/common_phase.hpp"
#include "hrgbench/estimator/fit_diagnostics.hpp"
#include "hrgbench/estimator/maximum_likelihood.hpp"

namespace hrgbench::estimator {
namespace {

using testing::AddNoise;
using testing::AddSpikes;
using testing::ApplyFrequencyRamp;
using testing::ProductionPlans;
using testing::ProductionTruth;

constexpr double kSigma = 1e-4;

std::vector<RunData> NoiseFree(double duration_s) {
  SimulationOptions truth = ProductionTruth();
  truth.sigma = 0.0;
  return SimulateRuns(ProductionPlans(duration_s, 500.0), truth);
}

void AddWhite(std::vector<RunData>* runs, std::uint64_t seed) {
  for (std::size_t r = 0; r < runs->size(); ++r) AddNoise(&(*runs)[r], kSigma, 0.0, seed * 97 + r);
}

MlOptions ModelOnly() {
  MlOptions o;
  o.phase_degree = 0;
  o.omega_uncertainty = false;
  o.outlier_threshold_sigma = 0.0;
  o.covariance = MlOptions::Covariance::kWhite;
  return o;
}

// Largest |a − b| / std of b over the ten parameters.
double LargestShift(const EstimateSummary& a, const EstimateSummary& b) {
  double largest = 0.0;
  for (int j = 0; j < 6; ++j)
    largest = std::max(largest, std::abs(a.delta[j] - b.delta[j]) / b.delta_std[j]);
  for (int k = 0; k < 4; ++k)
    largest = std::max(largest, std::abs(a.xi[k] - b.xi[k]) / b.xi_std[k]);
  return largest;
}

// Largest |estimate − truth| / reported std.
double LargestError(const EstimateSummary& s) {
  const SimulationOptions truth = ProductionTruth();
  double largest = 0.0;
  for (int j = 0; j < 6; ++j)
    largest = std::max(largest, std::abs(s.delta[j] - truth.delta[j]) / s.delta_std[j]);
  for (int k = 0; k < 4; ++k)
    largest = std::max(largest, std::abs(s.xi[k] - truth.xi[k]) / s.xi_std[k]);
  return largest;
}

bool MentionsRun(const EstimateSummary& s, int run, const std::string& what) {
  for (const std::string& p : s.diagnostics.problems)
    if (p.find("run " + std::to_string(run) + ":") == 0 && p.find(what) != std::string::npos)
      return true;
  return false;
}

// False alarms: 40 clean sessions of each design raise no problem. With the thresholds' five
// standard errors (residual ratio) and z = 6 (whiteness), the expected number is ~1e-5.
TEST(OutOfModelTest, CleanSessionsRaiseNoProblem) {
  int flagged = 0;
  double worst_ratio = 0.0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    std::vector<RunData> runs = NoiseFree(2.0);
    AddWhite(&runs, seed);
    const EstimateSummary s = EstimateMaximumLikelihood(runs);
    ASSERT_TRUE(s.IsUsable()) << s.Report();
    ASSERT_EQ(s.diagnostics.runs.size(), 6u);
    if (!s.diagnostics.Acceptable()) ++flagged;
    for (const RunFitDiagnostics& d : s.diagnostics.runs) {
      worst_ratio = std::max(worst_ratio, d.residual_ratio);
      EXPECT_EQ(d.outliers_removed, 0u);
    }
    EXPECT_EQ(s.diagnostics.covariance_kind, "white");
  }
  EXPECT_EQ(flagged, 0);
  EXPECT_LT(worst_ratio, 1.07);
}

// The paper's design (10 s at 100 Hz, |Ω| ≤ 1e-4 rad/s, 1000 samples a run) is weak but in model:
// no false alarm either.
TEST(OutOfModelTest, ThePapersDesignRaisesNoProblem) {
  SimulationOptions truth;
  truth.delta << -0.001, 0.3, 0, 0, 0, 0;
  truth.xi << 0.01, 0, 0, 0;
  truth.sigma = kSigma;
  std::vector<RunPlan> plans;
  for (int k = 0; k < 5; ++k) {
    RunPlan p;
    p.b = -0.4 + 0.2 * k;
    p.theta_rad = M_PI / 7 * k;
    p.omega_rad_s = -1e-4 + 5e-5 * k;
    p.sample_rate_hz = 100.0;
    p.duration_s = 10.0;
    plans.push_back(p);
  }
  int flagged = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    truth.seed = seed;
    MlOptions options;
    options.xi_estimated = kXi1Only;
    const EstimateSummary s = EstimateMaximumLikelihood(SimulateRuns(plans, truth), options);
    ASSERT_TRUE(s.IsUsable()) << s.Report();
    if (!s.diagnostics.Acceptable()) ++flagged;
  }
  EXPECT_EQ(flagged, 0);
}

// A common frequency ramp 0 → 3e-4 rad/s over each run (1e-8 of a 5 kHz carrier): the model alone
// is moved by many std and its residuals say so; the default (common phase of degree 2) absorbs it.
TEST(OutOfModelTest, AFrequencyRampIsAbsorbedByTheCommonPhase) {
  std::vector<RunData> clean = NoiseFree(2.0);
  std::vector<RunData> ramped = clean;
  for (RunData& r : ramped) ApplyFrequencyRamp(&r, 3e-4);
  AddWhite(&clean, 5);
  AddWhite(&ramped, 5);
  const EstimateSummary model_clean = EstimateMaximumLikelihood(clean, ModelOnly());
  const EstimateSummary model_ramped = EstimateMaximumLikelihood(ramped, ModelOnly());
  EXPECT_GT(LargestShift(model_ramped, model_clean), 3.0);
  EXPECT_FALSE(model_ramped.diagnostics.Acceptable());

  const EstimateSummary s_clean = EstimateMaximumLikelihood(clean);
  const EstimateSummary s_ramped = EstimateMaximumLikelihood(ramped);
  EXPECT_LT(LargestShift(s_ramped, s_clean), 0.05) << s_ramped.Report();
  EXPECT_TRUE(s_ramped.diagnostics.Acceptable()) << s_ramped.Report();
  // Noise-free, the fitted drift is the applied one: dω/dt = 3e-4 rad/s over the run's last
  // stamp, 2 − 1/500 s; and the parameters are the truth.
  std::vector<RunData> exact = NoiseFree(2.0);
  for (RunData& r : exact) ApplyFrequencyRamp(&r, 3e-4);
  const EstimateSummary s_exact = EstimateMaximumLikelihood(exact);
  for (const RunFitDiagnostics& d : s_exact.diagnostics.runs) {
    EXPECT_NEAR(d.common_frequency_drift_rad_s2, 3e-4 / (2.0 - 1.0 / 500.0), 1e-11);
    EXPECT_NEAR(d.common_frequency_rad_s, 0.0, 1e-11);
    EXPECT_TRUE(d.noise_free);
  }
  EXPECT_TRUE(s_exact.diagnostics.Acceptable()) << s_exact.Report();
  EXPECT_NEAR(s_exact.delta[kScaleFactor], ProductionTruth().delta[kScaleFactor], 1e-9);
}

// The same with a constant offset of the reference's frequency (0.01 rad/s): degree 1 suffices.
TEST(OutOfModelTest, AReferenceFrequencyOffsetIsAbsorbed) {
  std::vector<RunData> clean = NoiseFree(2.0);
  std::vector<RunData> offset = clean;
  for (RunData& r : offset) testing::ApplyCommonPhase(&r, [](double t) { return 0.01 * t; });
  AddWhite(&clean, 6);
  AddWhite(&offset, 6);
  const EstimateSummary s_clean = EstimateMaximumLikelihood(clean);
  const EstimateSummary s_offset = EstimateMaximumLikelihood(offset);
  EXPECT_LT(LargestShift(s_offset, s_clean), 0.05);
  std::vector<RunData> exact = NoiseFree(2.0);
  for (RunData& r : exact) testing::ApplyCommonPhase(&r, [](double t) { return 0.01 * t; });
  for (const RunFitDiagnostics& d : EstimateMaximumLikelihood(exact).diagnostics.runs)
    EXPECT_NEAR(d.common_frequency_rad_s, 0.01, 1e-11);
  EXPECT_GT(LargestShift(EstimateMaximumLikelihood(offset, ModelOnly()),
                         EstimateMaximumLikelihood(clean, ModelOnly())),
            3.0);
}

// Long runs with a reference offset and a drift (issue 23): 6 × 100 s, ±0.06 rad/s alternating over
// the runs and a 1 mHz/s ramp turn the runs by up to 37 rad. The common phase is started from the
// data (common_phase_start.hpp), so the fit lands where it does without them: noise-free, every
// parameter to 1e-8 of itself and each run's offset and drift exactly; with noise, at the same
// point as the fit of the same noise without the phase. Started at zero, it did not converge.
TEST(OutOfModelTest, ALongRunsReferenceOffsetAndDriftAreStartedFromTheData) {
  SimulationOptions truth = ProductionTruth();
  const std::vector<RunData> plain = SimulateRuns(ProductionPlans(100.0, 50.0), truth);
  constexpr double kDriftRadS2 = 2.0 * M_PI * 1e-3;
  const auto turned = [&](const std::vector<RunData>& runs) {
    std::vector<RunData> out = runs;
    for (std::size_t r = 0; r < out.size(); ++r) {
      const double offset = (r % 2 == 0 ? 0.06 : -0.06);
      testing::ApplyCommonPhase(&out[r],
                                [&](double t) { return offset * t + 0.5 * kDriftRadS2 * t * t; });
    }
    return out;
  };
  const EstimateSummary exact = EstimateMaximumLikelihood(turned(plain));
  ASSERT_TRUE(exact.Converged()) << exact.Report();
  for (int j = 0; j < 6; ++j)
    EXPECT_NEAR(exact.delta[j], truth.delta[j], 1e-8 * std::abs(truth.delta[j]) + 1e-13);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(exact.xi[k], truth.xi[k], 1e-8 * std::abs(truth.xi[k]));
  for (std::size_t r = 0; r < exact.diagnostics.runs.size(); ++r) {
    EXPECT_NEAR(exact.diagnostics.runs[r].common_frequency_rad_s, r % 2 == 0 ? 0.06 : -0.06, 1e-9);
    EXPECT_NEAR(exact.diagnostics.runs[r].common_frequency_drift_rad_s2, kDriftRadS2, 1e-11);
  }
  std::vector<RunData> noisy = plain;
  AddWhite(&noisy, 8);
  const EstimateSummary s_plain = EstimateMaximumLikelihood(noisy);
  const EstimateSummary s_turned = EstimateMaximumLikelihood(turned(noisy));
  ASSERT_TRUE(s_turned.Converged()) << s_turned.Report();
  EXPECT_TRUE(s_turned.diagnostics.Acceptable()) << s_turned.Report();
  EXPECT_LT(LargestShift(s_turned, s_plain), 0.05);
  MlOptions zero_start;
  zero_start.common_phase_start_from_data = false;
  const EstimateSummary s_zero = EstimateMaximumLikelihood(turned(noisy), zero_start);
  EXPECT_FALSE(s_zero.Converged() && s_zero.diagnostics.Acceptable() &&
               LargestShift(s_zero, s_plain) < 0.05)
      << s_zero.Report();
}

// Ω of run 1 off by 1e-5 rad/s, with σ_Ω = 1e-5 recorded (as the bench does; on these 10 s runs
// 1e-5 moves the model alone as 1e-6 moves 100 s runs): the model alone shifts by several std;
// the default, with Ω a nuisance under its recorded std, stays within one.
TEST(OutOfModelTest, AnOmegaErrorWithinItsRecordedStdStaysWithinTheReportedStd) {
  std::vector<RunData> clean = NoiseFree(10.0);
  AddWhite(&clean, 7);
  for (RunData& r : clean) r.omega_std_rad_s = 1e-5;
  std::vector<RunData> off = clean;
  off[0].omega_rad_s += 1e-5;
  EXPECT_GT(LargestShift(EstimateMaximumLikelihood(off, ModelOnly()),
                         EstimateMaximumLikelihood(clean, ModelOnly())),
            2.0);
  const EstimateSummary s_clean = EstimateMaximumLikelihood(clean);
  const EstimateSummary s_off = EstimateMaximumLikelihood(off);
  EXPECT_LT(LargestShift(s_off, s_clean), 1.0) << s_off.Report();
  EXPECT_TRUE(s_off.diagnostics.omega_nuisance);
  EXPECT_TRUE(s_off.diagnostics.Acceptable()) << s_off.Report();
  // The recorded uncertainty widens the reported std (δ3…δ6 are the ones Ω moves).
  const EstimateSummary exact = [&] {
    MlOptions o;
    o.omega_uncertainty = false;
    return EstimateMaximumLikelihood(clean, o);
  }();
  EXPECT_GT(
      s_clean.delta_std[kDampingAnisotropyCos] + s_clean.delta_std[kDampingAnisotropySin],
      1.2 * (exact.delta_std[kDampingAnisotropyCos] + exact.delta_std[kDampingAnisotropySin]));
}

// Ω of run 1 off by 1e-5 rad/s, ten times its recorded std: flagged, naming run 1; the estimate
// itself stays near the truth (the data pull Ω back). The data alone know run 1's Ω to ~1.2e-6
// rad/s here, so their offset is −1e-5 within 3.6e-6 (3 std).
TEST(OutOfModelTest, AnOmegaErrorBeyondItsRecordedStdIsFlagged) {
  std::vector<RunData> runs = NoiseFree(10.0);
  AddWhite(&runs, 8);
  for (RunData& r : runs) r.omega_std_rad_s = 1e-6;
  runs[0].omega_rad_s += 1e-5;
  const EstimateSummary s = EstimateMaximumLikelihood(runs);
  ASSERT_TRUE(s.IsUsable());
  EXPECT_TRUE(MentionsRun(s, 1, "recorded one")) << s.Report();
  EXPECT_NEAR(s.diagnostics.runs[0].omega_offset_data_rad_s, -1e-5, 3.6e-6);
  EXPECT_GT(std::abs(s.diagnostics.runs[0].omega_offset_in_std), 4.0);
  for (std::size_t r = 1; r < 6; ++r)
    EXPECT_LT(std::abs(s.diagnostics.runs[r].omega_offset_in_std), 4.0);
  EXPECT_LT(LargestError(s), 4.0);
}

// The Ω check under coloured noise the station declares (AR(1), ρ = 0.6: integrated correlation
// (1 + ρ)/(1 − ρ) = 4 samples): each recorded Ω is right within its recorded std, so the check's
// statistic must scatter as a standard normal. Taken with the white-noise information its RMS
// was 1.62 here (the carrier station's output filter made good units' fits look outside the
// model). 20 sessions × 6 runs: RMS within ±3.5 of its std (1/√240) of 1, no false alarm at 4.
TEST(OutOfModelTest, TheOmegaCheckScattersAsItClaimsUnderDeclaredColouredNoise) {
  constexpr double kRho = 0.6;
  MlOptions options;
  options.noise_shape.description = "AR(1), rho 0.6";
  for (double r = 1.0; r > 1e-4; r *= kRho) options.noise_shape.autocorrelation.push_back(r);
  double sum2 = 0.0, largest = 0.0;
  int count = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    std::vector<RunData> runs = NoiseFree(10.0);
    for (std::size_t r = 0; r < runs.size(); ++r) {
      AddNoise(&runs[r], kSigma, kRho, seed * 131 + r);
      runs[r].omega_std_rad_s = 3e-7;
    }
    const EstimateSummary s = EstimateMaximumLikelihood(runs, options);
    ASSERT_TRUE(s.IsUsable()) << s.Report();
    for (const RunFitDiagnostics& d : s.diagnostics.runs) {
      ASSERT_TRUE(std::isfinite(d.omega_offset_in_std));
      sum2 += d.omega_offset_in_std * d.omega_offset_in_std;
      largest = std::max(largest, std::abs(d.omega_offset_in_std));
      ++count;
    }
  }
  ASSERT_EQ(count, 120);
  const double rms = std::sqrt(sum2 / count);
  EXPECT_NEAR(rms, 1.0, 3.5 / std::sqrt(2.0 * count)) << "largest " << largest;
  EXPECT_LT(largest, 4.0);
}

// AR(1) noise, ρ = 0.9, marginal σ: the white-noise std understates the scatter several times
// (the model alone: RMS error/std ≈ 4). The default finds the colour, names the runs, and reports
// the sandwich std, which matches the scatter: RMS error/std within [0.75, 1.35] over 20 sessions
// of ten parameters (200 values: the RMS of standard normals has a 5 % standard error).
TEST(OutOfModelTest, ColouredNoiseIsFlaggedAndItsStdIsHonest) {
  double z2_default = 0.0, z2_model = 0.0;
  int n = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    std::vector<RunData> runs = NoiseFree(10.0);
    for (std::size_t r = 0; r < runs.size(); ++r) AddNoise(&runs[r], kSigma, 0.9, seed * 31 + r);
    const EstimateSummary s = EstimateMaximumLikelihood(runs);
    const EstimateSummary m = EstimateMaximumLikelihood(runs, ModelOnly());
    ASSERT_TRUE(s.IsUsable());
    EXPECT_EQ(s.diagnostics.covariance_kind, "sandwich");
    EXPECT_TRUE(MentionsRun(s, 1, "not white"));
    const SimulationOptions truth = ProductionTruth();
    for (int j = 0; j < 6; ++j) {
      z2_default += std::pow((s.delta[j] - truth.delta[j]) / s.delta_std[j], 2);
      z2_model += std::pow((m.delta[j] - truth.delta[j]) / m.delta_std[j], 2);
    }
    for (int k = 0; k < 4; ++k) {
      z2_default += std::pow((s.xi[k] - truth.xi[k]) / s.xi_std[k], 2);
      z2_model += std::pow((m.xi[k] - truth.xi[k]) / m.xi_std[k], 2);
    }
    n += 10;
  }
  const double rms_default = std::sqrt(z2_default / n);
  const double rms_model = std::sqrt(z2_model / n);
  EXPECT_GT(rms_model, 2.5);
  EXPECT_GT(rms_default, 0.75);
  EXPECT_LT(rms_default, 1.35);
}

// Ten ±100σ spikes in run 1: found, removed, said; the estimate is the one without them.
TEST(OutOfModelTest, SpikesAreRemovedAndSaid) {
  std::vector<RunData> clean = NoiseFree(2.0);
  AddWhite(&clean, 9);
  std::vector<RunData> spiked = clean;
  AddSpikes(&spiked[0], 10, 100.0 * kSigma, 11);
  const EstimateSummary s_clean = EstimateMaximumLikelihood(clean);
  const EstimateSummary s = EstimateMaximumLikelihood(spiked);
  EXPECT_EQ(s.diagnostics.runs[0].outliers_removed, 10u);
  EXPECT_NEAR(s.diagnostics.runs[0].largest_outlier_in_sigma, 100.0, 15.0);
  EXPECT_TRUE(s.diagnostics.Acceptable()) << s.Report();
  bool said = false;
  for (const std::string& w : s.warnings)
    said = said || w.find("removed as outliers") != std::string::npos;
  EXPECT_TRUE(said);
  EXPECT_LT(LargestShift(s, s_clean), 0.1);
  // Without removal the spikes are seen as outliers and in the residual ratio.
  const EstimateSummary kept = EstimateMaximumLikelihood(spiked, ModelOnly());
  EXPECT_GT(kept.diagnostics.runs[0].max_abs_residual_in_sigma, 50.0);
  EXPECT_GT(kept.diagnostics.runs[0].residual_ratio, 1.1);
}

// The statistics themselves, against what they must give on data of known kind.
TEST(FitDiagnosticsTest, DifferenceNoiseSigmaIgnoresTheSlowSignal) {
  std::vector<RunData> runs = NoiseFree(10.0);  // 5000 samples, amplitude 1, up to 0.6 rad/s
  AddNoise(&runs[5], 2e-4, 0.0, 3);
  // 20 000 values of a trimmed mean square: relative standard error √(2.63/(2·20 000)) = 0.8 %.
  EXPECT_NEAR(DifferenceNoiseSigma(runs[5].y), 2e-4, 0.04 * 2e-4);
}

TEST(FitDiagnosticsTest, LjungBoxOfWhiteAndColouredResiduals) {
  Eigen::Matrix4Xd white = Eigen::Matrix4Xd::Zero(4, 20000);
  RunData holder;
  holder.t_s.assign(20000, 0.0);
  holder.y = white;
  AddNoise(&holder, 1.0, 0.0, 1);
  const ResidualStatistics w = AnalyseResiduals(holder.y, 20);
  EXPECT_EQ(w.lags, 20);
  EXPECT_LT(std::abs(w.ljung_box_z), 4.0);  // N(0, 1) under white noise
  EXPECT_NEAR(w.lag1_autocorrelation, 0.0, 4.0 / std::sqrt(80000.0));
  EXPECT_NEAR(w.rms, 1.0, 0.02);
  EXPECT_NEAR(w.excess_kurtosis, 0.0, 0.15);  // std √(24/80 000) = 0.017
  holder.y.setZero();
  AddNoise(&holder, 1.0, 0.5, 2);
  const ResidualStatistics c = AnalyseResiduals(holder.y, 20);
  EXPECT_NEAR(c.lag1_autocorrelation, 0.5, 0.02);
  EXPECT_GT(c.ljung_box_z, 50.0);
  // 1 + 2·Σ 0.5^l·(1 − l/21) ≈ 2.9: the batch length scale of the sandwich.
  EXPECT_NEAR(c.integrated_correlation_samples, 2.9, 0.2);
}

// Wilson–Hilferty against tabulated χ² quantiles: χ²(80) at 0.999 is 124.84 (z = 3.090), at 0.5
// is 79.33 (z = 0).
TEST(FitDiagnosticsTest, ChiSquareNormalScoreMatchesTables) {
  EXPECT_NEAR(ChiSquareNormalScore(124.84, 80.0), 3.090, 0.02);
  EXPECT_NEAR(ChiSquareNormalScore(79.33, 80.0), 0.0, 0.01);
}

// The recurrence of e^{iψ} against the closed form, on a uniform grid with a dropped stretch, over
// 10 000 samples (160 resyncs). A rounding ε ≈ 1e-16 of the top factor e^{iΔ^Dψ} grows over the 64
// steps between resyncs to 64^D/D!·ε in ψ: 4e-12 for D = 3; the test allows 2e-11.
TEST(CommonPhaseTest, RecurrenceFollowsTheClosedForm) {
  const double q[3] = {0.7, -0.03, 2e-4};
  for (int degree = 0; degree <= 3; ++degree) {
    internal::CommonPhase phase(q, degree);
    double worst = 0.0;
    for (int k = 0; k < 10000; ++k) {
      if (k >= 4000 && k < 4013) continue;  // dropped samples: the step changes twice
      const double t = 1e-3 * k;
      const std::complex<double> expected = std::polar(1.0, phase.Psi(t));
      worst = std::max(worst, std::abs(phase.Next(t) - expected));
    }
    EXPECT_LT(worst, 2e-11) << "degree " << degree;
  }
}

}  // namespace
}  // namespace hrgbench::estimator
