#pragma once
// Shared by the bench tests: shipped configs, temporary session directories, one session run on
// the in-process simulated station.

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <random>
#include <string>

#include "app/station_factory.hpp"
#include "hrgbench/bench/bench_configs.hpp"
#include "hrgbench/bench/sequencer.hpp"

namespace hrgbench::testing {

inline std::filesystem::path ConfigPath(const std::string& name) {
  return std::filesystem::path(HRGBENCH_SOURCE_DIR) / "bench_configs" / name;
}

// A fresh directory name under the system temp dir (not created: sessions refuse non-empty dirs).
inline std::filesystem::path FreshDir(const std::string& stem) {
  std::random_device rd;
  return std::filesystem::temp_directory_path() /
         ("hrgbench-" + stem + "-" + std::to_string(rd()) + std::to_string(rd()));
}

struct BenchRun {
  bench::SessionResult result;
  std::filesystem::path dir;
  std::unique_ptr<app::Station> station;  // kept, so a test can look at the hardware afterwards
  std::unique_ptr<hw::RateTable> table;   // the wrapper the bench used instead, if any
};

// Loads the shipped configs (the station: station-sim.toml unless `station_file` says otherwise),
// lets `edit` change them (faults, shorter runs), opens the station and runs the session.
// `interrupt_when` (optional) is asked at every progress report whether to press Ctrl-C now.
// `wrap_table` (optional) puts a table of its own between the bench and the station's.
inline BenchRun RunOnSimulatedStation(
    const std::string& sequence, const std::string& limits,
    const std::function<void(bench::BenchConfigs&)>& edit = {},
    const std::function<bool(const bench::Progress&)>& interrupt_when = {},
    const std::function<std::unique_ptr<hw::RateTable>(hw::RateTable&)>& wrap_table = {},
    const std::string& station_file = "station-sim.toml") {
  BenchRun run;
  auto configs = bench::LoadBenchConfigs(ConfigPath(station_file), ConfigPath(sequence),
                                         limits.empty() ? "" : ConfigPath(limits));
  EXPECT_TRUE(configs) << (configs ? "" : configs.error().ToString());
  if (!configs) return run;
  if (edit) edit(*configs);
  auto station = app::OpenStation(configs->station);
  EXPECT_TRUE(station) << (station ? "" : station.error());
  if (!station) return run;
  run.station = std::move(*station);
  std::atomic<int> interrupts{0};
  bench::RunnerOptions options;
  options.unit_serial = "TEST-001";
  options.software_version = "test";
  options.simulation = run.station->simulation();
  options.interrupts = &interrupts;
  options.on_progress = [&](const bench::Progress& p) {
    if (interrupt_when && interrupt_when(p)) interrupts = 1;
  };
  run.dir = FreshDir("session");
  bench::BenchHardware hardware = run.station->hardware();
  if (wrap_table) {
    run.table = wrap_table(*hardware.table);
    hardware.table = run.table.get();
  }
  run.result = bench::RunSession(*configs, hardware, run.dir, options);
  return run;
}

}  // namespace hrgbench::testing
