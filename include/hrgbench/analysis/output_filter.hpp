#pragma once
// What the gyro's electronics do to the pick-off noise before it reaches the bench: their output
// low-pass filter, declared by the station ([gyro] output_filter, output_filter_order,
// output_filter_cutoff_hz), recorded in session.json (electronics.output_filter, typed and
// validated by the session layer's one reader: session::ElectronicsRecord) and turned into the
// noise shape the fit's checks assume (estimator/noise_shape.hpp).
//
// Why declared and not measured: the filter is a design constant of the electronics, and a shape
// estimated from the data would also absorb colour that is a misfit (a drift, a wrong rate) or
// noise the electronics should not have. A declaration that does not explain the data is flagged
// by the fit like any other misfit.
//
// The declaration itself (OutputFilter) is plain data of the session layer
// (session/electronics.hpp): the station declares it and the record keeps it; this is what the
// analysis makes of it. Pure functions; never throw except std::bad_alloc.

#include <cstdint>
#include <expected>
#include <nlohmann/json.hpp>
#include <string>

#include "hrgbench/estimator/noise_shape.hpp"
#include "hrgbench/session/electronics.hpp"
#include "hrgbench/session/session_record.hpp"

namespace hrgbench::bench {

// {"kind": "none"} or {"kind": "butterworth", "order": 4, "cutoff_hz": 200.0}.
nlohmann::json OutputFilterJson(const OutputFilter& filter);

// The noise shape of the filter's output sampled at `sample_rate_hz`; an error (one line, naming
// the values) when the filter's memory is too long for the estimator's bound (a cutoff far below
// the sample rate).
std::expected<estimator::NoiseShape, std::string> NoiseShapeOf(const OutputFilter& filter,
                                                               double sample_rate_hz);

// The output filter a session's record declares (electronics.output_filter): kNone when the record
// has none (sessions before the declaration existed, hrg-sim sessions).
OutputFilter RecordedOutputFilter(const session::ElectronicsRecord& electronics);

// How long after release the filter's output still carries the release: the time after which the
// step response of the ANALOG Butterworth of that order and cutoff is, by a bound on the sum of
// its modes' magnitudes, within `fraction` of its final value. Why a step: at release the
// electronics' filters hold the held wave's demodulated value, and the free run's input differs
// from it by a jump (the 2·f0 image and the wave's motion starting at once); the response to any
// such jump of size ≤ 1 is bounded by the step's modes. With the default 1e-6 of the wave's
// amplitude the transient is 1 % of a σ_y ≈ 1e-4 pick-off noise: 29 ms for the 4th-order 200 Hz
// filter (its slowest mode decays at 2π·200·sin(π/8) = 481 /s). 0 for kNone.
inline constexpr double kReleaseSettlingFraction = 1e-6;
double ReleaseSettlingS(const OutputFilter& filter, double fraction = kReleaseSettlingFraction);

// "4th-order Butterworth, 200 Hz" or "none".
std::string OutputFilterName(const OutputFilter& filter);

// The noise shape a session's record declares: electronics.output_filter at the session's sample
// rate; white when the record has none (sessions before the declaration existed, hrg-sim
// sessions). An error naming the values when there is no sample rate to sample the filter at, or
// the filter's memory is too long (NoiseShapeOf).
std::expected<estimator::NoiseShape, std::string> RecordedNoiseShape(
    const session::ElectronicsRecord& electronics, double sample_rate_hz);

}  // namespace hrgbench::bench
