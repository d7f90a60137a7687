#pragma once
// What a fit left, summarised for the page: the residuals' density histogram (to set beside the
// Gaussian of the fit's noise σ̂) and their one-sided power spectral density by Welch's method (to
// set beside the white-noise level 2σ̂²/fs). Both read the whole run and return a bounded number
// of points (the bins; half a segment per channel), so a run's figure costs the same whatever its
// length. Internal to src/report. Pure functions, thread-safe; they allocate their results.

#include <cstddef>
#include <span>
#include <vector>

namespace hrgbench::report::internal {

// The values' density over `bins` equal bins of [−half_width, half_width]: density[b] = count in
// bin b / (total · bin width), so a histogram of N(0, σ²) samples approaches the normal density.
// Values outside the range (and NaN) are counted, not binned. half_width > 0 and bins ≥ 1, else
// the result has no bins.
struct DensityHistogram {
  std::vector<double> edges;    // bins + 1, increasing
  std::vector<double> density;  // bins
  std::size_t total = 0;        // finite values seen
  std::size_t outside = 0;      // finite values beyond ±half_width
};
DensityHistogram HistogramOf(std::span<const double> values, double half_width, std::size_t bins);

// One-sided power spectral density by Welch's method: segments of `segment_length` samples
// (the largest power of two ≤ min(max_segment_length, n), at least 8) overlapping by half, each
// segment's mean removed and a Hann window applied, the periodograms averaged. Density in
// units²/Hz, scaled so that white noise of std σ reads 2σ²/fs at every frequency but 0 and fs/2
// (where a one-sided density is not doubled). The k-th sample is first[k·stride], k < n.
// Fewer than 8 samples or fs ≤ 0: an empty result.
struct PowerSpectrum {
  std::vector<double> frequency_hz;  // 0, fs/M, …, fs/2 (M/2 + 1 values)
  std::vector<double> density;       // parallel to frequency_hz
  std::size_t segment_length = 0;    // M
  std::size_t segments = 0;          // averaged
};
PowerSpectrum WelchSpectrum(const double* first, std::ptrdiff_t stride, std::size_t n,
                            double sample_rate_hz, std::size_t max_segment_length = 512);

}  // namespace hrgbench::report::internal
