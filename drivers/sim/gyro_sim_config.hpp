#pragma once
// The hrg-gyro-sim configuration file (TOML; the shipped example is
// drivers/sim/gyro_sim.example.toml). Declared, validated data (STYLE rule 10): unknown tables and
// keys are errors, and every error names file, line, key and value.
//
//   [model]       delta (6 numbers), xi (4), sigma, seed
//   [electronics] excite_time_s, resonant_frequency_hz, temperature_c, supports_fd
//   [omega]       source = "constant" | "modbus", omega_rad_s (constant), modbus_host,
//                 modbus_port, earth_rate_rad_s (added to the table's rate), poll_period_ms
//   [faults]      the GyroSimFaults fields by name

#include <cstdint>
#include <expected>
#include <string>
#include <string_view>

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

// Parses TOML text; `source_name` is used in messages (the file name).
std::expected<GyroSimFileConfig, std::string> ParseGyroSimConfig(std::string_view toml_text,
                                                                 std::string_view source_name);
std::expected<GyroSimFileConfig, std::string> LoadGyroSimConfig(const std::string& path);

}  // namespace hrgbench::drivers::sim
