#pragma once
// Shared by the bench tests: shipped configs, temporary session directories, one session run on
// the in-process simulated station.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "app/station_factory.hpp"
#include "hrgbench/bench/sequencer/sequencer.hpp"
#include "hrgbench/config/bench_configs.hpp"
#include "removed_at_end.hpp"

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

// Loads the shipped configs, lets `edit` change them, and opens the station into `station`;
// std::nullopt (and a test failure) when either fails.
inline std::optional<bench::BenchConfigs> OpenShippedStation(
    const std::string& station_file, const std::string& sequence, const std::string& limits,
    const std::function<void(bench::BenchConfigs&)>& edit, std::unique_ptr<app::Station>& station) {
  auto configs = bench::LoadBenchConfigs(ConfigPath(station_file), ConfigPath(sequence),
                                         limits.empty() ? "" : ConfigPath(limits));
  EXPECT_TRUE(configs) << (configs ? "" : configs.error().ToString());
  if (!configs) return std::nullopt;
  if (edit) edit(*configs);
  auto opened = app::OpenStation(configs->station);
  EXPECT_TRUE(opened) << (opened ? "" : opened.error());
  if (!opened) return std::nullopt;
  station = std::move(*opened);
  return std::move(*configs);
}

// Answers every operator prompt at once (the shipped production sequence has two), as
// `hrg-bench run --prompts confirm` does; counts what it was shown.
class ConfirmEveryPrompt final : public bench::PromptAnswers {
 public:
  void Show(const bench::PromptRequest& prompt) override { shown.push_back(prompt.id); }
  std::optional<bench::PromptReply> Wait(std::chrono::milliseconds) override {
    return bench::PromptReply{true, "test", "auto"};
  }
  std::vector<std::string> shown;
};

struct BenchRun {
  RemovedAtEnd removes_dir;  // first: destroyed last, after the station that wrote into it
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
    const std::string& station_file = "station-sim.toml", bench::PromptAnswers* prompts = nullptr) {
  BenchRun run;
  ConfirmEveryPrompt confirm;
  auto configs = OpenShippedStation(station_file, sequence, limits, edit, run.station);
  if (!configs) return run;
  std::atomic<int> interrupts{0};
  bench::RunnerOptions options;
  options.unit_serial = "TEST-001";
  options.software_version = "test";
  options.simulation = run.station->simulation();
  options.interrupts = &interrupts;
  options.on_progress = [&](const bench::Progress& p) {
    if (interrupt_when && interrupt_when(p)) interrupts = 1;
  };
  options.prompts = prompts != nullptr ? prompts : &confirm;
  run.dir = FreshDir("session");
  run.removes_dir = RemovedAtEnd(run.dir);
  bench::BenchHardware hardware = run.station->hardware();
  if (wrap_table) {
    run.table = wrap_table(*hardware.table);
    hardware.table = run.table.get();
  }
  run.result = bench::RunSession(*configs, hardware, run.dir, options);
  return run;
}

struct FixtureRun {
  RemovedAtEnd removes_fixture_dir;           // every unit's folder is under it
  std::vector<bench::SessionResult> results;  // one per fitted position, in order
  std::vector<std::filesystem::path> dirs;
  std::unique_ptr<app::Station> station;
};

// A session of every unit on the fixture of `station_file` (default station-sim-fixture.toml),
// serials "FX-<position>", each unit's folder under one fresh fixture folder.
inline FixtureRun RunFixtureOnSimulatedStation(
    const std::string& sequence, const std::string& limits,
    const std::function<void(bench::BenchConfigs&)>& edit = {},
    const std::function<bool(const bench::Progress&)>& interrupt_when = {},
    const std::string& station_file = "station-sim-fixture.toml",
    bench::PromptAnswers* prompts = nullptr) {
  FixtureRun run;
  ConfirmEveryPrompt confirm;
  auto configs = OpenShippedStation(station_file, sequence, limits, edit, run.station);
  if (!configs) return run;
  const std::filesystem::path fixture = FreshDir("fixture");
  run.removes_fixture_dir = RemovedAtEnd(fixture);
  std::vector<bench::UnitSession> units;
  const bench::BenchHardware& hardware = run.station->hardware();
  for (std::size_t i = 0; i < hardware.units.size(); ++i) {
    bench::UnitSession unit;
    unit.serial = "FX-" + hardware.units[i].position;
    unit.dir = fixture / (hardware.units[i].position + "-" + unit.serial);
    unit.simulation = run.station->simulation(i);
    run.dirs.push_back(unit.dir);
    units.push_back(std::move(unit));
  }
  std::atomic<int> interrupts{0};
  bench::RunnerOptions options;
  options.software_version = "test";
  options.interrupts = &interrupts;
  options.on_progress = [&](const bench::Progress& p) {
    if (interrupt_when && interrupt_when(p)) interrupts = 1;
  };
  options.prompts = prompts != nullptr ? prompts : &confirm;
  run.results = bench::RunSessions(*configs, hardware, units, options);
  return run;
}

}  // namespace hrgbench::testing
