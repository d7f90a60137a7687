#pragma once
// The shape of the pick-off noise as the electronics deliver it: its autocorrelation ρ[k] at the
// output sample spacing, declared by the station (the electronics' output filter is a design
// constant), not estimated from the data — so that colour the declaration does not explain still
// shows up as a misfit.
//
// Why it matters: real electronics low-pass the demodulated channels before they decimate, so
// neighbouring samples' noise is correlated. Two of the fit's checks assume white noise
// (fit_diagnostics.hpp): the model-free noise σ from 4th differences (var Δ⁴y = 70σ² only for white
// noise; for filtered noise the differences cancel most of it) and the Ljung–Box whiteness of the
// residuals (the filter's own colour reads as a misfit). With a declared shape:
//  - σ comes from 4th differences taken `stride` samples apart, with stride past the noise's
//    memory, and their variance factor Σ_j Σ_l c_j·c_l·ρ[stride·|j − l|] (c = 1, −4, 6, −4, 1),
//    which is 70 for white noise and within 2 % of it at the chosen stride, so the estimate hardly
//    depends on how exact the declaration is. The slow signal's leak grows as (ω·stride·dt)⁴: still
//    negligible while ω is far below the filter's cutoff, which it always is;
//  - whiteness is judged on the lags beyond the declared memory (from `first_lag` on), with the
//    null distribution of those sample autocorrelations from Bartlett's formula
//    (Cov(r_l, r_m) = (A[l − m] + A[l + m])/N, A = ρ⋆ρ) and the Ljung–Box sum matched to a scaled
//    χ² (Satterthwaite): a frequency drift, a wrong rate or extra coloured noise still correlate
//    the residuals at those lags; the filter's colour does not;
//  - the covariance of the estimate is the sandwich form (maximum_likelihood.hpp), honest under the
//    declared colour.
// White noise (the default) gives exactly the white-noise checks: stride 1, factor 70, lags 1..L,
// the χ²(4L) null.
//
// Pure functions of the shape; allocate; never throw except std::bad_alloc.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace hrgbench::estimator {

// Longest declared memory, in output samples (a bound on what a declaration may cost).
inline constexpr std::size_t kMaxNoiseShapeLags = 4096;
// Highest Butterworth order ButterworthNoiseShape takes (and a station may declare).
inline constexpr int kMaxButterworthOrder = 12;
// Standard error of the residual ratio of white noise is this over √N (N samples of four
// channels); derived in DifferenceNoiseModel below.
inline constexpr double kResidualRatioStandardErrorScale = 0.451;

struct NoiseShape {
  // ρ[0..K] at the output sample spacing, ρ[0] = 1, ρ[k] = 0 beyond K. One element or none: white.
  std::vector<double> autocorrelation;
  std::string description = "white";  // what was declared, for the record and the messages

  bool IsWhite() const noexcept { return autocorrelation.size() <= 1; }
  // ρ at any lag (symmetric; 0 beyond the declared memory).
  double Rho(long lag) const noexcept;
  // ρ[0] = 1, every |ρ[k]| ≤ 1, finite, at most kMaxNoiseShapeLags + 1 values.
  bool IsValid(std::string* why) const;
};

// The noise of a Butterworth low-pass of `order` (1..kMaxButterworthOrder) with cutoff `cutoff_hz`
// fed with white noise, sampled every 1/sample_rate_hz (decimation by taking every n-th sample
// keeps the autocorrelation at the output lags). Closed form: with the analog filter's
// left-half-plane poles p_k = ω_c·e^{iπ(2k + n − 1)/(2n)}, |H(iω)|² = 1/(1 + (ω/ω_c)^{2n}) has the
// autocorrelation R(τ) = Σ_k −p_k·e^{p_k·|τ|}/(2n) (residues of the inverse Fourier integral closed
// to the left), so ρ[k] = R(k/f_s)/R(0). A digital filter designed by the bilinear transform at a
// converter rate far above the cutoff (the real chain, drivers/sim) differs by (cutoff/converter
// rate)² relative. nullopt when the arguments are out of range or the memory exceeds
// kMaxNoiseShapeLags samples (a cutoff far below the sample rate: say so rather than truncate).
std::optional<NoiseShape> ButterworthNoiseShape(int order, double cutoff_hz, double sample_rate_hz);

// How far the declared noise's memory reaches: the smallest lag from which every |ρ| is at most
// 0.01 (1 for white noise).
int NoiseMemoryLags(const NoiseShape& shape);

// The 4th-difference noise estimate for this shape: differences `stride` samples apart
// (NoiseMemoryLags), their variance per unit noise variance, and the standard-error scale of the
// residual ratio (its standard error is scale/√N for N samples of four channels).
struct DifferenceNoiseModel {
  int stride = 1;
  double variance_factor = 70.0;
  // ratio² = m_r/m_d with m_r the residuals' and m_d the scaled differences' mean square; for
  // Gaussian noise Var(m_a)·N = 2·Σ_k R_aa[k]² and Cov(m_a, m_b)·N = 2·Σ_k R_ab[k]², so
  // Var(ratio) = (S_rr + S_dd − 2·S_rd)/(8N) over four channels: 0.451²/N for white noise.
  double ratio_standard_error_scale = kResidualRatioStandardErrorScale;
};
DifferenceNoiseModel DifferenceNoiseModelFor(const NoiseShape& shape);

// The null distribution of the whiteness statistic for this shape: Ljung–Box over `lags` lags of
// each of four channels from `first_lag` on, approximately scale·χ²(dof).
struct WhitenessNull {
  int first_lag = 1;
  int lags = 20;
  double scale = 1.0;  // g: E[Q] = g·dof, Var[Q] = 2·g²·dof
  double dof = 80.0;   // 4·lags for white noise
};
WhitenessNull WhitenessNullFor(const NoiseShape& shape, int lags);

}  // namespace hrgbench::estimator
