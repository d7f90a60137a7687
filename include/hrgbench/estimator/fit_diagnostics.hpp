#pragma once
// Is the fit right? Statistics of a run's data and of its residuals that do not assume the model:
//
//  - noise σ from the data alone: the 4th differences of y remove any slow signal (the slow
//    variables move by ω·dt ≪ 1 per sample, so their 4th difference is ~(ω·dt)⁴ of the amplitude)
//    and leave white noise with variance C(8,4)·σ² = 70·σ²; σ comes from their mean square, trimmed
//    at 6 robust σ (so spikes do not count). At most (ω·dt)⁴ of the signal leaks in: negligible
//    below ω·dt = 0.05 (8 rad/s at 1 kHz).
//  - residual ratio: the residual RMS over that σ. 1 when the model explains everything but white
//    noise; more when something the model lacks (a frequency drift, a wrong Ω, coloured noise) is
//    left in the residuals. Its standard error for white noise over N samples of four channels is
//    0.451/√N (derived in docs/estimator/methods.md: the Δ⁴ sequence has Σρ² = 2.63 and
//    correlates 0.62 with the residuals' mean square), so the check allows
//    max(residual_ratio_max, 1 + 5·0.451/√N).
//  - whiteness: the Ljung–Box statistic Q = N(N+2)·Σ_{l=1..L} ρ_l²/(N − l) of each channel's
//    residuals, summed over the four channels; for white residuals Q ~ χ²(4L). Reported with its
//    Wilson–Hilferty normal score z (≈ N(0, 1) when white; large and positive when coloured).
//  - outliers: the largest |residual|/σ_robust and the excess kurtosis (0 for Gaussian residuals).
//
// Pure functions; allocate (not for a real-time loop); never throw except std::bad_alloc.

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "hrgbench/estimator/noise_shape.hpp"
#include "hrgbench/estimator/parameters.hpp"

namespace hrgbench::estimator {

// Thresholds beyond which the estimator warns and the bench's verdict refuses to pass a fit
// (bench_configs: [fit] in a limits file overrides them). Defaults chosen from the false-alarm rate
// measured over seeds (README: "Is the fit right?").
struct FitQualityLimits {
  double residual_ratio_max = 1.05;      // residual RMS / model-free noise σ
  double whiteness_z_max = 6.0;          // Ljung–Box normal score
  double omega_offset_max_in_std = 4.0;  // |Ω the data say − Ω recorded| in std of the difference

  bool IsValid(std::string* why) const;
};

struct RunFitDiagnostics {
  int run_id = 0;
  std::size_t samples = 0;                  // used in the fit (after outliers were removed)
  double noise_sigma = kNaN;                // from 4th differences of y, robust (model-free)
  double residual_rms = kNaN;               // per channel and sample
  double residual_ratio = kNaN;             // residual_rms / noise_sigma
  double residual_ratio_threshold = kNaN;   // what it was judged against (ResidualRatioThreshold)
  double lag1_autocorrelation = kNaN;       // of the residuals, pooled over the channels
  int whiteness_lags = 0;                   // L
  double whiteness_q = kNaN;                // Ljung–Box Q over four channels, χ²(4L) when white
  double whiteness_z = kNaN;                // its normal score
  double max_abs_residual_in_sigma = kNaN;  // largest |residual| / robust residual σ
  double excess_kurtosis = kNaN;
  std::size_t outliers_removed = 0;             // samples removed as outliers before the final fit
  double largest_outlier_in_sigma = kNaN;       // of the removed ones (NaN when none)
  double common_frequency_rad_s = kNaN;         // fitted common phase: dψ/dt at the start (q_1)
  double common_frequency_drift_rad_s2 = kNaN;  // 2·q_2 (NaN when the degree is below 2)
  double omega_offset_rad_s = kNaN;             // fitted Ω − recorded Ω (NaN when Ω was held)
  double omega_offset_data_rad_s = kNaN;        // what the data alone say it is (without the prior)
  // The data's offset in std of (recorded error ⊕ data error): N(0, 1) when the recorded Ω is right
  // within its recorded std; large when the data contradict it.
  double omega_offset_in_std = kNaN;
  // The data carry no measurable noise (a noise-free simulation): whiteness is not judged and the
  // ratio is taken against 1e-10 of the signal.
  bool noise_free = false;
};

struct FitDiagnostics {
  std::vector<RunFitDiagnostics> runs;  // in the order of the runs given
  // Which covariance the summary reports: "white" (σ̂²·(JᵀJ)⁻¹) or "sandwich" (H⁻¹·S·H⁻¹ with the
  // score covariance S from batch means of the residuals' score, honest under coloured residuals).
  std::string covariance_kind = "white";
  std::size_t sandwich_batch_samples = 0;  // batch length of the sandwich (0 when not computed)
  // Largest ratio, over the estimated parameters, of the sandwich std to the white-noise std
  // (NaN when not computed). About 1 for white residuals.
  double sandwich_to_white_std_max = kNaN;
  int phase_degree = 0;  // degree of the common-phase nuisance in the fit
  // The noise shape the checks assumed (MlOptions::noise_shape's description; "white" by
  // default), the stride of the 4th differences that estimated σ, and the first lag the
  // whiteness statistic judged (1 for white noise; past the declared noise's memory otherwise).
  std::string noise_shape = "white";
  int difference_stride = 1;
  int whiteness_first_lag = 1;
  bool omega_nuisance = false;        // whether recorded Ω uncertainties entered the fit
  FitQualityLimits limits;            // what the checks below were judged against
  std::vector<std::string> problems;  // one line per failed check, naming the run

  bool Acceptable() const { return problems.empty(); }
};

// Model-free σ of each channel's white noise from the 4th differences of y (trimmed mean square).
// Needs at least 5 samples (else NaN).
double DifferenceNoiseSigma(const Eigen::Matrix4Xd& y);
// The same for noise of a declared shape (noise_shape.hpp): differences model.stride samples apart,
// variance model.variance_factor·σ². Needs 4·stride + 1 samples.
double DifferenceNoiseSigma(const Eigen::Matrix4Xd& y, const DifferenceNoiseModel& model);

// The residual ratio a run of `samples` samples may reach: the limit, or five standard errors of
// the ratio above 1 when that is wider (short runs). The scale is the noise shape's
// (DifferenceNoiseModel::ratio_standard_error_scale; 0.451 for white noise).
double ResidualRatioThreshold(const FitQualityLimits& limits, std::size_t samples,
                              double standard_error_scale = kResidualRatioStandardErrorScale);

struct ResidualStatistics {
  double rms = kNaN;
  double robust_sigma = kNaN;  // 1.4826·median|r|
  double lag1_autocorrelation = kNaN;
  double ljung_box_q = kNaN;
  int lags = 0;
  double ljung_box_z = kNaN;
  double max_abs_in_sigma = kNaN;
  double excess_kurtosis = kNaN;
  double integrated_correlation_samples = kNaN;  // 1 + 2·Σ_{l≤L} ρ_l (≥ 1): the batch length scale
};

// 1.4826·median|r| over the four channels: a Gaussian σ that outliers do not move. Above 2^16
// values the median is taken over an evenly strided subset of 2^16 of them (its relative standard
// error is then ~0.5 %, ample for a scale that decides 6σ and 8σ thresholds).
double RobustSigma(const Eigen::Matrix4Xd& values);

// Statistics of one run's residuals (one column per sample) with `lags` lags (clamped to N/4),
// whiteness against white noise's null (χ²(4L)).
ResidualStatistics AnalyseResiduals(const Eigen::Matrix4Xd& residuals, int lags);
// ... against a declared noise shape's null: lags null.first_lag on, Q/scale ~ χ²(dof).
ResidualStatistics AnalyseResiduals(const Eigen::Matrix4Xd& residuals, const WhitenessNull& null);

// Normal score of a χ²(dof) value (Wilson–Hilferty): ≈ N(0, 1) under the null.
double ChiSquareNormalScore(double q, double dof);

}  // namespace hrgbench::estimator
