#include "residual_figures.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "figure_spec.hpp"
#include "html_text.hpp"
#include "residual_statistics.hpp"

namespace hrgbench::report::internal {

void AddResidualFigures(int run_id, const Eigen::Matrix4Xd& residuals, double noise_sigma,
                        double sample_rate_hz, nlohmann::json* figures) {
  const auto n = static_cast<std::size_t>(residuals.cols());
  if (n < 8) return;
  const std::string id = std::to_string(run_id);
  const std::span<const double> pooled(residuals.data(), 4 * n);
  double sum_squares = 0.0;
  std::size_t finite = 0;
  for (const double v : pooled) {
    if (!std::isfinite(v)) continue;
    sum_squares += v * v;
    ++finite;
  }
  const double rms = finite > 0 ? std::sqrt(sum_squares / static_cast<double>(finite)) : 0.0;
  const bool recorded_sigma = std::isfinite(noise_sigma) && noise_sigma > 0.0;
  const double sigma = recorded_sigma ? noise_sigma : rms;
  if (!(sigma > 0.0)) return;  // an exact fit: nothing to draw
  const std::string sigma_text =
      (recorded_sigma ? "the fit's noise σ̂ = " : "the residuals' RMS (no σ̂ recorded) = ") +
      Readable(sigma);

  // Wide enough for residuals broader than σ̂ to show as such, not as counts off the chart.
  const double half_width = 5.0 * std::max(sigma, rms);
  constexpr std::size_t kBins = 50;
  const DensityHistogram h = HistogramOf(pooled, half_width, kBins);
  std::vector<double> step_x{h.edges.front()}, step_y{0.0};
  for (std::size_t b = 0; b < h.density.size(); ++b) {
    step_x.insert(step_x.end(), {h.edges[b], h.edges[b + 1]});
    step_y.insert(step_y.end(), {h.density[b], h.density[b]});
  }
  step_x.push_back(h.edges.back());
  step_y.push_back(0.0);
  std::vector<double> gauss_x, gauss_y;
  constexpr int kGaussPoints = 101;
  for (int k = 0; k < kGaussPoints; ++k) {
    const double x = -half_width + 2.0 * half_width * k / (kGaussPoints - 1);
    gauss_x.push_back(x);
    gauss_y.push_back(std::exp(-0.5 * (x / sigma) * (x / sigma)) /
                      (sigma * std::sqrt(2.0 * std::numbers::pi)));
  }
  nlohmann::json histogram = LineFigure(
      "residual-histogram-run-" + id,
      "Run " + id + ": the residuals y − ŷ of all four channels (" + std::to_string(h.total) +
          " values), density per bin, against the Gaussian of " + sigma_text + " (dashed); " +
          std::to_string(h.outside) + " beyond ±" + Readable(half_width),
      "y − ŷ", "density [1/y]", {});
  histogram["series"].push_back(XySeries("residuals, y1…y4 pooled", step_x, step_y));
  histogram["series"].push_back(XySeries("N(0, σ̂²)", gauss_x, gauss_y, true));
  figures->push_back(std::move(histogram));

  if (!(sample_rate_hz > 0.0) || !std::isfinite(sample_rate_hz)) return;
  const char* names[] = {"y1 − ŷ1", "y2 − ŷ2", "y3 − ŷ3", "y4 − ŷ4"};
  nlohmann::json spectrum;
  for (int c = 0; c < 4; ++c) {
    // At least ~15 segments averaged (a short run's spectrum is otherwise noise on noise), at
    // most 512 samples each (a long run's resolution fs/512 is ample for lines and colour).
    const PowerSpectrum s = WelchSpectrum(residuals.data() + c, 4, n, sample_rate_hz,
                                          std::clamp<std::size_t>(n / 8, 8, 512));
    // 0 and fs/M (the segments' means removed: the Hann window spreads that over both) and fs/2
    // (not doubled) read low by construction, not by the noise: left out.
    if (s.density.size() < 4) return;
    const std::vector<double> f(s.frequency_hz.begin() + 2, s.frequency_hz.end() - 1);
    const std::vector<double> d(s.density.begin() + 2, s.density.end() - 1);
    if (c == 0) {
      spectrum = LineFigure(
          "residual-spectrum-run-" + id,
          "Run " + id + ": one-sided power spectral density of each channel's residuals (Welch: " +
              std::to_string(s.segment_length) + "-sample Hann segments, half overlap, " +
              std::to_string(s.segments) + " averaged) against the white noise of " + sigma_text +
              ", 2σ̂²/fs = " + Readable(2.0 * sigma * sigma / sample_rate_hz) + " y²/Hz (dashed)",
          "f [Hz]", "PSD [y²/Hz]", f);
      spectrum["y_log"] = true;
    }
    spectrum["series"].push_back(Series(names[c], d));
  }
  const auto points = spectrum["x"].size();
  spectrum["series"].push_back(Series(
      "white noise of σ̂", std::vector<double>(points, 2.0 * sigma * sigma / sample_rate_hz), true));
  figures->push_back(std::move(spectrum));
}

}  // namespace hrgbench::report::internal
