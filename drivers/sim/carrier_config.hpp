#pragma once
// The [carrier] table of hrg-gyro-sim's config file (gyro_sim_config.hpp) and a simulated station's
// [simulated.carrier] table are one table, read by the config layer's one reader
// (hrgbench/config/simulated_carrier.hpp: keys, defaults, bounds); this maps what it read onto the
// simulator's CarrierOptions. Key by key: drivers/sim/README.md.

#include <expected>

#include "hrgbench/config/config_error.hpp"
#include "hrgbench/config/simulated_carrier.hpp"
#include "hrgbench/config/toml_reader.hpp"
#include "sim/carrier_options.hpp"

namespace hrgbench::drivers::sim {

// `base` with every field the table declares set from `config`; the rest (quantise, the
// cross-talk's stage) kept.
CarrierOptions CarrierOptionsFrom(const bench::SimulatedCarrierConfig& config,
                                  CarrierOptions base = {});

// Reads the table (bench::ReadSimulatedCarrier) into *options (CarrierOptionsFrom).
std::expected<void, config_file::ConfigError> ReadCarrierTable(config_file::TableReader& reader,
                                                               CarrierOptions* options);

}  // namespace hrgbench::drivers::sim
