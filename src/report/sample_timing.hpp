#pragma once
// How evenly a run was sampled: the report's capture-quality rows. The std is taken about the
// mean step in two passes: the one-pass form (Σdt²/n − mean²) cancels catastrophically when the
// steps agree to ~1e-12 of themselves, and printed 1.2e-9 s beside a largest deviation of 9e-15 s.

#include <cstddef>
#include <span>

namespace hrgbench::report {

struct SampleTiming {
  double interval_s;       // mean step, s (NaN with fewer than 2 samples)
  double jitter_std_s;     // std of the steps about that mean, s
  double jitter_max_s;     // largest |step − nominal|, s
  std::size_t long_steps;  // steps longer than 1.5 nominal intervals (lost samples)
};

// `nominal_rate_hz` not finite or ≤ 0: the median step is the nominal one.
SampleTiming MeasureSampleTiming(std::span<const double> t_s, double nominal_rate_hz);

}  // namespace hrgbench::report
