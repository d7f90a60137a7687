#pragma once
// What the operator panel offers and shows: the station's allowed sequences and limits, and the
// station's recent sessions.
//
// The allowed list is what the station file's [offers] names (config/station_offers.hpp), in its
// order, each of which must load and pass the cross-file checks with the station
// (LoadBenchConfigs) or the panel does not start (the loader's message names file, line and key).
// Without [offers] (or one of its lists): every sequence-*.toml and limits-*.toml beside the
// station file that loads; one that does not is left out and logged. The page selects the
// station's defaults when it loads (never merely the first in name order), and offers "no limits"
// only when the station says so ([offers] no_limits, never on a real station; a station with no
// limits file at all runs without). The page picks by id (the index in these lists), never by
// path: no path from the page reaches the file system.
//
// Recent sessions: from the station's results store when it has one ([results] url: the station's
// sessions wherever they were recorded), else the sessions folder's sub-folders with a
// session.json (read with a size bound); newest first. Not thread-safe: the lists are built once;
// the recent sessions are read per call.

#include <cstdint>
#include <expected>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hrgbench/config/bench_configs.hpp"

namespace hrgbench::app {

struct AllowedConfig {
  std::filesystem::path file;
  std::string name;         // [sequence] / [limits] name
  std::string description;  // sequences: runs and free-run time
  // What the page shows of it before Start (the plan): a sequence's {warmup {min_s, window_s,
  // max_drift_c, timeout_s}, runs [{omega_rad_s, a, b, theta_rad, free_run_s, sample_rate_hz}]};
  // a limits file's {limits [{quantity, min, max}], fit_checks [names, per run]}.
  nlohmann::json plan;
};

struct PanelCatalog {
  std::filesystem::path station_file;
  bench::StationConfig station;
  std::vector<AllowedConfig> sequences;  // at least one
  std::vector<AllowedConfig> limits;     // may be empty (then sessions run without limits)
  std::size_t default_sequence = 0;      // index into sequences
  std::size_t default_limits = 0;        // index into limits (when there are any)
  bool no_limits = false;  // a session may run without limits (none offered, or declared)
};

// Fails when the station does not load or no sequence beside it does (the message says which).
std::expected<PanelCatalog, std::string> LoadPanelCatalog(const std::filesystem::path& station);

// At most `count` sessions, newest first: [{name, unit, station, outcome, reason, started,
// report}] (report: the page's URL of the report, or null). Unreadable folders are skipped.
nlohmann::json RecentSessions(const std::filesystem::path& sessions_dir, std::size_t count);

// The same rows from the results store at `url`: the newest `count` sessions of `station`. A row's
// name is its folder's name; its report is linked only when that folder is in `sessions_dir`
// (the page can open nothing else). Error: the store cannot be opened or read (the message says
// which and why).
std::expected<nlohmann::json, std::string> RecentSessionsFromStore(
    const std::string& url, const std::string& station, const std::filesystem::path& sessions_dir,
    std::size_t count);

// The session folder name as the page may ask for it (for the report link): a direct sub-folder of
// the sessions folder, no "..", no leading '.'. True when `name` is that and exists.
bool IsSessionName(const std::filesystem::path& sessions_dir, std::string_view name);

}  // namespace hrgbench::app
