#pragma once
// The [simulated.carrier] table of a station file (physics = "carrier"), read into
// SimulatedCarrierConfig with the strict reader: every key optional, bounds at the key, the
// cross-checks (sample_rate_hz ≥ 4·frequency_hz, filter_cutoff_hz ≤ frequency_hz/4, even
// filter_order, split < f0), keys of the other reference mode and unknown keys are errors.
// Private to hrgbench_config (station_loader.cpp).

#include <expected>

#include "hrgbench/config/config_error.hpp"
#include "hrgbench/config/station_config.hpp"
#include "hrgbench/config/toml_reader.hpp"

namespace hrgbench::bench::internal {

std::expected<SimulatedCarrierConfig, config_file::ConfigError> ReadSimulatedCarrier(
    config_file::TableReader& reader);

}  // namespace hrgbench::bench::internal
