#pragma once
// The two figures of what a run's fit left (issue 26 §4), from the run's residuals y − ŷ:
//  - residual-histogram-run-N: the four channels' residuals pooled, as a density histogram (50
//    bins over ±5 times the larger of σ̂ and their RMS) against the Gaussian N(0, σ̂²) the fit
//    assumed (dashed): a wide, skewed or heavy-tailed histogram is noise the model does not have.
//  - residual-spectrum-run-N: each channel's one-sided PSD (Welch, Hann, segments of n/8 up to 512
//    samples, half overlap; residual_statistics.hpp) on a log axis, against the white-noise level
//    2σ̂²/fs (dashed): lines, a rising low end or a roll-off are colour the white-noise model
//    ignores.
// Each figure holds at most ~1100 numbers whatever the run's length. Internal to src/report.

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace hrgbench::report::internal {

// `residuals` 4 × n (channel per row); `noise_sigma` the fit's σ̂ for this run (not finite or not
// positive: the residuals' own RMS stands in, and the caption says so); `sample_rate_hz` > 0 for
// the spectrum (else it is not drawn). Appends the figures to `figures`; nothing when n < 8.
void AddResidualFigures(int run_id, const Eigen::Matrix4Xd& residuals, double noise_sigma,
                        double sample_rate_hz, nlohmann::json* figures);

}  // namespace hrgbench::report::internal
