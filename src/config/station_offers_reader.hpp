#pragma once
// [offers] of a station file (hrgbench/config/station_offers.hpp), read by the station loader.

#include <expected>

#include "hrgbench/config/station_config.hpp"
#include "hrgbench/config/toml_reader.hpp"

namespace hrgbench::bench::internal {

// `reader`: the [offers] table. The names' shape is checked here, their files by the panel.
std::expected<StationOffers, config_file::ConfigError> ReadOffers(config_file::TableReader& reader,
                                                                  StationKind kind);

}  // namespace hrgbench::bench::internal
