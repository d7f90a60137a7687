#pragma once
// Copies of the config files inside the session (internal to the sequencer).

#include <expected>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "hrgbench/config/bench_configs.hpp"

namespace hrgbench::bench::internal {

// The [results] url the session ran with when the station file wrote a relative SQLite path
// (resolved against that file's folder), relative to the session folder.
inline constexpr const char* kResultsUrlCopy = "config/results-url.txt";

// Writes <dir>/config/{station,sequence,limits}.toml atomically from the files the configs were
// loaded from (limits only when there was a limits file).
std::expected<void, std::string> SaveConfigs(const BenchConfigs& configs,
                                             const std::filesystem::path& dir);

// The same files as (path relative to a session folder, contents), for SessionHeader::files_first.
std::expected<std::vector<std::pair<std::string, std::string>>, std::string> ConfigCopies(
    const BenchConfigs& configs);

}  // namespace hrgbench::bench::internal
