// A run's Ω from the table's rate readings and from its angle (include/hrgbench/bench/
// run_omega.hpp has the error model this implements).

#include "hrgbench/bench/capture/run_omega.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hrgbench::bench {

std::string_view ToString(OmegaSource source) noexcept {
  switch (source) {
    case OmegaSource::kAngle:
      return "angle";
    case OmegaSource::kRate:
      return "rate";
  }
  return "?";
}

void RateReadingsMean::Add(double measured_rate_rad_s) noexcept {
  sum_ += measured_rate_rad_s;
  sum2_ += measured_rate_rad_s * measured_rate_rad_s;
  ++n_;
}

OmegaEstimate RateReadingsMean::Result() const noexcept {
  OmegaEstimate e;
  e.readings = n_;
  if (n_ == 0) return e;
  const auto n = static_cast<double>(n_);
  e.omega_rad_s = sum_ / n;
  if (n_ > 1) {
    const double variance = std::max(0.0, (sum2_ - n * e.omega_rad_s * e.omega_rad_s) / (n - 1));
    e.std_error_rad_s = std::sqrt(variance / n);
  }
  return e;
}

void AngleRateFit::Add(const hw::RateTableAngle& reading) {
  if (!reading.valid || reading.counts_per_rev == 0) {
    ++invalid_;
    return;
  }
  if (points_.empty()) {
    counts_per_rev_ = reading.counts_per_rev;
    unwrapped_ = 0;
  } else {
    if (reading.counts_per_rev != counts_per_rev_ && problem_.empty()) {
      problem_ = "the encoder resolution changed within the run (" +
                 std::to_string(counts_per_rev_) + " then " +
                 std::to_string(reading.counts_per_rev) + " counts/rev)";
    }
    // The difference modulo 2^32 read as a signed number: exact while the table turns less than
    // 2^31 counts between two readings.
    unwrapped_ += static_cast<std::int32_t>(reading.count - last_count_);
  }
  last_count_ = reading.count;
  points_.push_back({reading.t_ns, unwrapped_, std::max<std::int64_t>(0, reading.window_ns)});
}

OmegaEstimate AngleRateFit::Result() const {
  OmegaEstimate e;
  e.readings = points_.size();
  if (!problem_.empty() || points_.size() < 2) return e;
  const double q = 2.0 * std::numbers::pi / counts_per_rev_;
  const std::int64_t t0 = points_.front().t_ns;
  const auto t_s = [t0](const Point& p) { return static_cast<double>(p.t_ns - t0) * 1e-9; };
  const auto phi = [q](const Point& p) { return static_cast<double>(p.counts) * q; };

  // Weighted least squares of phi on t; returns the slope, fills S_tt and chi^2.
  const auto fit = [&](double omega_for_weights, double* s_tt, double* chi2) {
    double sw = 0.0, swt = 0.0, swp = 0.0;
    for (const Point& p : points_) {
      const double w_s = static_cast<double>(p.window_ns) * 1e-9;
      const double var = (q * q + omega_for_weights * omega_for_weights * w_s * w_s) / 12.0;
      const double w = 1.0 / var;
      sw += w;
      swt += w * t_s(p);
      swp += w * phi(p);
    }
    const double t_mean = swt / sw, phi_mean = swp / sw;
    double stt = 0.0, stp = 0.0;
    for (const Point& p : points_) {
      const double w_s = static_cast<double>(p.window_ns) * 1e-9;
      const double w = 12.0 / (q * q + omega_for_weights * omega_for_weights * w_s * w_s);
      const double dt = t_s(p) - t_mean;
      stt += w * dt * dt;
      stp += w * dt * (phi(p) - phi_mean);
    }
    const double slope = stp / stt;
    double c2 = 0.0;
    for (const Point& p : points_) {
      const double w_s = static_cast<double>(p.window_ns) * 1e-9;
      const double w = 12.0 / (q * q + omega_for_weights * omega_for_weights * w_s * w_s);
      const double r = phi(p) - phi_mean - slope * (t_s(p) - t_mean);
      c2 += w * r * r;
    }
    *s_tt = stt;
    *chi2 = c2;
    return slope;
  };

  const double span_s = t_s(points_.back());
  if (!(span_s > 0.0)) return e;  // every reading at one instant: no slope
  // The jitter term needs Ω: the end points give it well enough (to q / T) for the weights.
  const double omega0 = phi(points_.back()) / span_s;
  double s_tt = 0.0, chi2 = 0.0;
  const double omega = fit(omega0, &s_tt, &chi2);
  if (!std::isfinite(omega) || !(s_tt > 0.0)) return e;
  double std_error = 1.0 / std::sqrt(s_tt);
  const auto n = static_cast<double>(points_.size());
  if (points_.size() > 2) std_error *= std::max(1.0, std::sqrt(chi2 / (n - 2)));
  // Slow table: the same quantisation error read again; no better than the end points.
  const double counts_between = std::abs(omega) * span_s / q / (n - 1);
  if (counts_between < kCorrelatedCounts) {
    std_error = std::max(std_error, q / (std::sqrt(6.0) * span_s));
  }
  e.omega_rad_s = omega;
  e.std_error_rad_s = std_error;
  return e;
}

}  // namespace hrgbench::bench
