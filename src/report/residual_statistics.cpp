#include "residual_statistics.hpp"

#include <cmath>
#include <numbers>
#include <utility>

namespace hrgbench::report::internal {
namespace {

// In-place iterative radix-2 FFT of (re, im), n = re.size() a power of two, with the twiddles
// cos/sin(2πk/n), k < n/2, precomputed once per spectrum. Plain doubles, not std::complex: its
// multiplication checks for infinities (__muldc3) and made the report's spectra 5× slower. The
// segments are a few hundred samples: no library is worth its dependency here.
void Fft(std::vector<double>& re, std::vector<double>& im, const std::vector<double>& cos_table,
         const std::vector<double>& sin_table) {
  const std::size_t n = re.size();
  for (std::size_t i = 1, j = 0; i < n; ++i) {
    std::size_t bit = n >> 1;
    for (; (j & bit) != 0; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) {
      std::swap(re[i], re[j]);
      std::swap(im[i], im[j]);
    }
  }
  for (std::size_t len = 2; len <= n; len <<= 1) {
    const std::size_t half = len / 2, stride = n / len;
    for (std::size_t i = 0; i < n; i += len) {
      for (std::size_t k = 0; k < half; ++k) {
        const double wr = cos_table[k * stride], wi = -sin_table[k * stride];
        const std::size_t a = i + k, b = a + half;
        const double vr = re[b] * wr - im[b] * wi, vi = re[b] * wi + im[b] * wr;
        re[b] = re[a] - vr;
        im[b] = im[a] - vi;
        re[a] += vr;
        im[a] += vi;
      }
    }
  }
}

}  // namespace

DensityHistogram HistogramOf(std::span<const double> values, double half_width, std::size_t bins) {
  DensityHistogram h;
  if (!(half_width > 0.0) || !std::isfinite(half_width) || bins == 0) return h;
  const double width = 2.0 * half_width / static_cast<double>(bins);
  for (std::size_t b = 0; b <= bins; ++b)
    h.edges.push_back(-half_width + width * static_cast<double>(b));
  std::vector<std::size_t> counts(bins, 0);
  for (const double v : values) {
    if (!std::isfinite(v)) continue;
    ++h.total;
    const double at = (v + half_width) / width;
    if (at < 0.0 || at >= static_cast<double>(bins)) {
      ++h.outside;
      continue;
    }
    ++counts[static_cast<std::size_t>(at)];
  }
  h.density.resize(bins, 0.0);
  if (h.total == 0) return h;
  for (std::size_t b = 0; b < bins; ++b)
    h.density[b] = static_cast<double>(counts[b]) / (static_cast<double>(h.total) * width);
  return h;
}

PowerSpectrum WelchSpectrum(const double* first, std::ptrdiff_t stride, std::size_t n,
                            double sample_rate_hz, std::size_t max_segment_length) {
  PowerSpectrum s;
  if (n < 8 || !(sample_rate_hz > 0.0) || !std::isfinite(sample_rate_hz)) return s;
  std::size_t m = 8;
  while (m * 2 <= n && m * 2 <= max_segment_length) m *= 2;
  std::vector<double> window(m);
  double window_power = 0.0;  // Σw²
  for (std::size_t k = 0; k < m; ++k) {
    // The periodic Hann window (as scipy.signal.welch's default): its overlap-by-half sums flat.
    window[k] = 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * static_cast<double>(k) /
                                     static_cast<double>(m));
    window_power += window[k] * window[k];
  }
  const std::size_t half = m / 2;
  std::vector<double> cos_table(half), sin_table(half);
  for (std::size_t k = 0; k < half; ++k) {
    const double angle = 2.0 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(m);
    cos_table[k] = std::cos(angle);
    sin_table[k] = std::sin(angle);
  }
  std::vector<double> sum(half + 1, 0.0);
  std::vector<double> re(m), im(m);
  const auto at = [&](std::size_t k) { return first[static_cast<std::ptrdiff_t>(k) * stride]; };
  for (std::size_t begin = 0; begin + m <= n; begin += half) {
    double mean = 0.0;
    for (std::size_t k = 0; k < m; ++k) mean += at(begin + k);
    mean /= static_cast<double>(m);
    for (std::size_t k = 0; k < m; ++k) {
      re[k] = (at(begin + k) - mean) * window[k];
      im[k] = 0.0;
    }
    Fft(re, im, cos_table, sin_table);
    for (std::size_t k = 0; k <= half; ++k) sum[k] += re[k] * re[k] + im[k] * im[k];
    ++s.segments;
  }
  const double scale = 1.0 / (sample_rate_hz * window_power * static_cast<double>(s.segments));
  s.segment_length = m;
  s.frequency_hz.resize(half + 1);
  s.density.resize(half + 1);
  for (std::size_t k = 0; k <= half; ++k) {
    s.frequency_hz[k] = sample_rate_hz * static_cast<double>(k) / static_cast<double>(m);
    s.density[k] = sum[k] * scale * (k == 0 || k == half ? 1.0 : 2.0);
  }
  return s;
}

}  // namespace hrgbench::report::internal
