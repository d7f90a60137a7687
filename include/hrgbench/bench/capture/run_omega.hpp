#pragma once
// A run's Ω: the mean rate of the table over the capture, measured from what the rate table
// reports while the run goes on (the sequencer reads it at the release, at every heartbeat read,
// about every 20 ms, and once after the capture). Two measurements, both kept in the record:
//
//   RateReadingsMean  the mean of the table's measured-rate readings; standard error s / sqrt(n)
//                     (readings 20 ms apart taken as independent: the readout noise varies, not
//                     the rate). A table's rate reading is its controller's filtered derivative of
//                     the angle, so its noise does not average down faster than 1 / sqrt(n).
//   AngleRateFit      the slope of a weighted straight-line fit of the unwrapped encoder angle
//                     against the bench clock. The angle's change is the exact integral of the
//                     true rate, so its error does not grow with the run and the slope's error
//                     falls as T^-3/2 (see the error model below).
//
// Error model of one angle reading i (the fit's weights and its standard error; derived here):
//   - quantisation: the encoder reports floor(phi / q), q = 2 pi / counts_per_rev: an error
//     uniform on [-q, 0], variance q^2 / 12 (its mean -q/2 is common to all and leaves the slope);
//   - read-time jitter: the table sampled its encoder at an unknown instant within the read's
//     window (t_i ± w_i / 2, hw::RateTableAngle); taking it uniform there, the time error has
//     variance w_i^2 / 12, which is an angle error of variance Omega^2 w_i^2 / 12;
//   so sigma_i^2 = q^2 / 12 + Omega^2 w_i^2 / 12, independent between readings while the table
// turns many counts between them and the link's delays are independent. With weights
// 1 / sigma_i^2, the slope's variance is 1 / S_tt, S_tt = sum (t_i - t_w)^2 / sigma_i^2 (t_w the
// weighted mean time). What the model leaves out (the encoder's read noise, a rate that wobbles
// about its mean, correlated delays) shows in the residuals: the standard error is inflated by
// sqrt(chi^2 / (N - 2)) when that exceeds 1 (the Birge ratio; N > 2). When the table turns less
// than kCorrelatedCounts counts between readings (Omega near 0), their quantisation errors are
// the same error read again and the fit cannot beat its end points: the standard error is then
// at least q / (sqrt(6) T), two independent uniform errors over the span T.
//
// Units: rad/s, rad, s; time stamps ns on the bench clock. Ω here is the table's alone: the caller
// adds the Earth-rate component. Not real-time: Add may allocate (call Reserve first); the
// sequencer's main thread uses these, never the capture thread. Not thread-safe.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "hrgbench/hw/rate_table.hpp"

namespace hrgbench::bench {

// Which measurement a run's Ω came from (RunEnd::omega_source).
enum class OmegaSource { kAngle, kRate };
std::string_view ToString(OmegaSource source) noexcept;  // "angle", "rate"

struct OmegaEstimate {
  double omega_rad_s = std::numeric_limits<double>::quiet_NaN();      // NaN: no estimate
  double std_error_rad_s = std::numeric_limits<double>::quiet_NaN();  // NaN: not known
  std::uint64_t readings = 0;                                         // readings it used
  bool valid() const noexcept { return std::isfinite(omega_rad_s); }
};

class RateReadingsMean {
 public:
  void Add(double measured_rate_rad_s) noexcept;
  // Mean and its standard error (NaN with fewer than 2 readings); NaN mean with none.
  OmegaEstimate Result() const noexcept;

 private:
  double sum_ = 0.0;
  double sum2_ = 0.0;
  std::uint64_t n_ = 0;
};

class AngleRateFit {
 public:
  // Counts moved between readings below which their quantisation errors are taken as one.
  static constexpr double kCorrelatedCounts = 10.0;

  void Reserve(std::size_t readings) { points_.reserve(readings); }
  // Takes one reading. Invalid ones (the table does not vouch for the position) are counted and
  // left out. A resolution that changes within the run spoils the fit (problem()).
  void Add(const hw::RateTableAngle& reading);
  // The slope and its standard error (model above); NaN with fewer than 2 valid readings, when
  // they all share one time stamp, or when problem() is set.
  OmegaEstimate Result() const;

  std::uint64_t valid_readings() const noexcept { return points_.size(); }
  std::uint64_t invalid_readings() const noexcept { return invalid_; }
  // Why there is no Ω from the angle although readings were valid; empty otherwise.
  const std::string& problem() const noexcept { return problem_; }

 private:
  struct Point {
    std::int64_t t_ns;
    std::int64_t counts;  // unwrapped, relative to the first valid reading
    std::int64_t window_ns;
  };
  std::vector<Point> points_;
  std::uint32_t counts_per_rev_ = 0;
  std::uint32_t last_count_ = 0;
  std::int64_t unwrapped_ = 0;
  std::uint64_t invalid_ = 0;
  std::string problem_;
};

}  // namespace hrgbench::bench
