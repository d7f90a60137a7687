#include "hrgbench/analysis/output_filter.hpp"

#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <vector>

#include "hrgbench/session/session_record_keys.hpp"

namespace hrgbench::bench {

nlohmann::json OutputFilterJson(const OutputFilter& filter) {
  namespace keys = session::keys;
  if (filter.kind == OutputFilterKind::kNone) return {{keys::kKind, keys::kFilterNone}};
  return {{keys::kKind, keys::kFilterButterworth},
          {keys::kOrder, filter.order},
          {keys::kCutoffHz, filter.cutoff_hz}};
}

std::expected<estimator::NoiseShape, std::string> NoiseShapeOf(const OutputFilter& filter,
                                                               double sample_rate_hz) {
  if (filter.kind == OutputFilterKind::kNone) return estimator::NoiseShape{};
  const auto shape = estimator::ButterworthNoiseShape(static_cast<int>(filter.order),
                                                      filter.cutoff_hz, sample_rate_hz);
  if (!shape) {
    return std::unexpected(
        "output filter: a Butterworth of order " + std::to_string(filter.order) + " at " +
        std::to_string(filter.cutoff_hz) + " Hz sampled at " + std::to_string(sample_rate_hz) +
        " Hz has a memory longer than " + std::to_string(estimator::kMaxNoiseShapeLags) +
        " samples (or the values are out of range): raise the cutoff or lower the rate");
  }
  return *shape;
}

OutputFilter RecordedOutputFilter(const session::ElectronicsRecord& electronics) {
  return electronics.output_filter.value_or(OutputFilter{});
}

std::expected<estimator::NoiseShape, std::string> RecordedNoiseShape(
    const session::ElectronicsRecord& electronics, double sample_rate_hz) {
  const OutputFilter declared = RecordedOutputFilter(electronics);
  if (declared.kind == OutputFilterKind::kNone) return estimator::NoiseShape{};
  if (!(sample_rate_hz > 0.0))
    return std::unexpected(
        "electronics.output_filter: the session has no sample rate to sample the filter at");
  return NoiseShapeOf(declared, sample_rate_hz);
}

double ReleaseSettlingS(const OutputFilter& filter, double fraction) {
  if (filter.kind == OutputFilterKind::kNone || !(filter.cutoff_hz > 0.0) || filter.order < 1 ||
      !(fraction > 0.0 && fraction < 1.0))
    return 0.0;
  // H(s) = ωc^n / Π(s − p_k), poles p_k = ωc·e^{iπ(2k+n−1)/(2n)}, k = 1 … n. The step response is
  // 1 + Σ_k (r_k/p_k)·e^{p_k·t} with r_k = ωc^n / Π_{j≠k}(p_k − p_j), so its distance from 1 is at
  // most B(t) = Σ_k |r_k/p_k|·e^{Re(p_k)·t}, which falls monotonically: bisect B(t) = fraction.
  const int n = static_cast<int>(filter.order);
  const double wc = 2.0 * std::numbers::pi * filter.cutoff_hz;
  std::vector<std::complex<double>> poles(static_cast<std::size_t>(n));
  for (int k = 1; k <= n; ++k)
    poles[static_cast<std::size_t>(k - 1)] =
        std::polar(wc, std::numbers::pi * (2.0 * k + n - 1.0) / (2.0 * n));
  std::vector<double> weight(poles.size()), rate(poles.size());
  for (std::size_t k = 0; k < poles.size(); ++k) {
    std::complex<double> product = 1.0;
    for (std::size_t j = 0; j < poles.size(); ++j)
      if (j != k) product *= (poles[k] - poles[j]) / wc;  // scaled by ωc: no overflow at order 12
    weight[k] = std::abs(1.0 / (product * (poles[k] / wc)));
    rate[k] = poles[k].real();
  }
  const auto bound = [&](double t_s) {
    double sum = 0.0;
    for (std::size_t k = 0; k < poles.size(); ++k) sum += weight[k] * std::exp(rate[k] * t_s);
    return sum;
  };
  double low = 0.0, high = 1.0 / filter.cutoff_hz;
  while (bound(high) > fraction) high *= 2.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (low + high);
    (bound(mid) > fraction ? low : high) = mid;
  }
  return high;
}

std::string OutputFilterName(const OutputFilter& filter) {
  if (filter.kind == OutputFilterKind::kNone) return "none";
  const std::int64_t n = filter.order;
  const char* suffix = (n % 100 >= 11 && n % 100 <= 13) ? "th"
                       : n % 10 == 1                    ? "st"
                       : n % 10 == 2                    ? "nd"
                       : n % 10 == 3                    ? "rd"
                                                        : "th";
  char cutoff[32];
  std::snprintf(cutoff, sizeof cutoff, "%g", filter.cutoff_hz);
  return std::to_string(n) + suffix + "-order Butterworth, " + cutoff + " Hz";
}

}  // namespace hrgbench::bench
