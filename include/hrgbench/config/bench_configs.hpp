#pragma once
// The three files of a bench session, loaded and checked together: what `hrg-bench check S Q L`
// validates and what `hrg-bench run` starts from.
//
// Besides each file's own checks, the combination is checked (each error names the file and line
// where the fix belongs):
//   - every run's |Ω| is within the station's table.max_rate_rad_s (sequence file, the run's line);
//   - every run's sample rate fits the gyro link it will really use: classic CAN carries at most
//     hw::kMaxSampleRateClassicCanHz, CAN FD (gyro.fd = true, simulated stations too)
//     hw::kMaxSampleRateCanFdHz (sequence file);
//   - every limited parameter can be determined by the sequence's rates, Earth rate included
//     (δ2 needs Ω ≠ 0, ξ two distinct Ω; estimator/identifiability.hpp) (limits file, its line).
//
// Not thread-safe; not for real-time use; never throws (except std::bad_alloc).

#include <expected>
#include <filesystem>
#include <string>
#include <vector>

#include "hrgbench/config/config_error.hpp"
#include "hrgbench/config/limits_config.hpp"
#include "hrgbench/config/sequence_config.hpp"
#include "hrgbench/config/station_config.hpp"
#include "hrgbench/hw/gyro_link_load.hpp"

namespace hrgbench::bench {

struct BenchConfigs {
  StationConfig station;
  SequenceConfig sequence;
  LimitsConfig limits;  // empty (no file, no limits) when loaded without a limits file
};

// `limits_path` empty: no limits file (`hrg-bench run` without --limits; nothing is judged).
std::expected<BenchConfigs, config_file::ConfigError> LoadBenchConfigs(
    const std::filesystem::path& station_path, const std::filesystem::path& sequence_path,
    const std::filesystem::path& limits_path);

// The cross-file checks alone, on configs already loaded (for configs parsed from memory).
// Among them: each bus must carry every run's sample rate for all its units within
// hw::kMaxPlannedBusShare (hw/gyro_link_load.hpp, worst-case stuffing, the reference phase
// planned as sent).
std::expected<void, config_file::ConfigError> CheckBenchConfigs(const BenchConfigs& configs);

// The busiest run's load on the busiest bus (the one carrying the most units: all of theirs), for
// `hrg-bench check` to print.
struct PlannedBusLoad {
  hw::GyroLinkLoad load;
  std::uint32_t sample_rate_hz = 0;  // per unit
  std::size_t units = 1;             // units on that bus
  // "can0 at 1000 kbit/s", "the simulated bus at 1000 kbit/s, FD data ...",
  // "can1 (2 units: A, B) at 1000 kbit/s"; EachBusLoad: the interface's name alone ("can1")
  std::string bus;
  std::vector<std::string> positions;  // EachBusLoad: the fitted positions on it, in order
};
PlannedBusLoad BusiestRunLoad(const BenchConfigs& configs);
// Every bus of the station's fitted positions (in the order of its first position), each with
// its busiest run's load.
std::vector<PlannedBusLoad> EachBusLoad(const BenchConfigs& configs);
std::string Percent(double share);  // "27.0 %"

}  // namespace hrgbench::bench
