#pragma once
// What the gyro's electronics do to the pick-off noise before it reaches the bench: their output
// low-pass filter, declared by the station ([gyro] output_filter, output_filter_order,
// output_filter_cutoff_hz), recorded in session.json ("electronics": {"output_filter": ...}) and
// turned into the noise shape the fit's checks assume (estimator/noise_shape.hpp).
//
// Why declared and not measured: the filter is a design constant of the electronics, and a shape
// estimated from the data would also absorb colour that is a misfit (a drift, a wrong rate) or
// noise the electronics should not have. A declaration that does not explain the data is flagged
// by the fit like any other misfit.
//
// Pure functions; never throw except std::bad_alloc.

#include <cstdint>
#include <expected>
#include <nlohmann/json.hpp>
#include <string>

#include "hrgbench/estimator/noise_shape.hpp"

namespace hrgbench::bench {

enum class OutputFilterKind {
  kNone,         // the electronics pass white pick-off noise (or filter far above the output rate)
  kButterworth,  // a Butterworth low-pass of `order` with cutoff `cutoff_hz`, then decimation
};

struct OutputFilter {
  OutputFilterKind kind = OutputFilterKind::kNone;
  std::int64_t order = 4;    // 1 … estimator::kMaxButterworthOrder
  double cutoff_hz = 200.0;  // > 0
};

// {"kind": "none"} or {"kind": "butterworth", "order": 4, "cutoff_hz": 200.0}.
nlohmann::json OutputFilterJson(const OutputFilter& filter);

// The noise shape of the filter's output sampled at `sample_rate_hz`; an error (one line, naming
// the values) when the filter's memory is too long for the estimator's bound (a cutoff far below
// the sample rate).
std::expected<estimator::NoiseShape, std::string> NoiseShapeOf(const OutputFilter& filter,
                                                               double sample_rate_hz);

// The noise shape a session's record declares: "electronics"."output_filter" of session.json at
// the session's sample rate; white when the record has none (sessions before the declaration
// existed, hrg-sim sessions). An error naming the field and value when it is malformed.
std::expected<estimator::NoiseShape, std::string> RecordedNoiseShape(
    const nlohmann::json& session_document, double sample_rate_hz);

}  // namespace hrgbench::bench
