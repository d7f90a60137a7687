#pragma once
// The hrg-gyro-sim configuration file (TOML; the shipped example is
// drivers/sim/gyro_sim.example.toml). Declared, validated data (STYLE rule 10), read with the
// project's one strict config-file reader (hrgbench/config/toml_reader.hpp) like the bench's
// configs: unknown tables and keys are errors, and every error is a ConfigError naming file, line,
// key and value (`sim.toml:3: key 'model.sigmaa' = 2: unknown key (allowed here: ...)`). The
// ranges are GyroSimOptions::IsValid's and the integer fields' own; numbers must be finite; a
// host name is 1 to 255 bytes of printable text; the file is at most 1 MiB and a regular file.
//
//   [model]       physics = "slow" (default) | "carrier"; delta (6 numbers), xi (4), sigma (slow
//                 only), seed
//   [carrier]     physics = "carrier" only: the mode, pick-off path and electronics
//                 (carrier_config.hpp; keys in drivers/sim/README.md)
//   [electronics] excite_time_s, resonant_frequency_hz, temperature_c, supports_fd
//   [omega]       source = "constant" | "modbus", omega_rad_s (constant), modbus_host,
//                 modbus_port, earth_rate_rad_s (added to the table's rate), poll_period_ms
//   [faults]      the GyroSimFaults fields by name

#include <cstdint>
#include <expected>
#include <filesystem>
#include <string>
#include <string_view>

#include "hrgbench/config/config_error.hpp"
#include "sim/gyro_sim_options.hpp"

namespace hrgbench::drivers::sim {

struct OmegaConfig {
  enum class Source { kConstant, kModbus };
  Source source = Source::kConstant;
  double omega_rad_s = 0.0;  // kConstant: Ω itself
  std::string modbus_host = "127.0.0.1";
  int modbus_port = 502;
  double earth_rate_rad_s = 0.0;  // kModbus: Ω = table rate + this (vertical Earth rate)
  int poll_period_ms = 20;        // kModbus: how often the table's measured rate is read
};

struct GyroSimFileConfig {
  GyroSimOptions options;
  OmegaConfig omega;
};

// Parses TOML text; `file` is only used in messages. Allocates; no global state.
std::expected<GyroSimFileConfig, config_file::ConfigError> ParseGyroSimConfig(
    std::string_view toml_text, const std::filesystem::path& file);
std::expected<GyroSimFileConfig, config_file::ConfigError> LoadGyroSimConfig(
    const std::filesystem::path& file);

}  // namespace hrgbench::drivers::sim
