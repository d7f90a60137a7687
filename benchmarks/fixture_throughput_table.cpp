// Units per table-hour: the production sequence run once for a fixture of N simulated units, each
// on its own in-process bus (N = 1, 2, 4, 8), on the simulated station faster than real time,
// through bench::RunSessions exactly as `hrg-bench run --serial ...` drives it (the estimate of
// each unit included; the HTML report and the results upload, which the program adds per unit,
// not). Then the same sequence for 4 units at 1 kHz on separate buses and on one shared bus
// (nodes 0-3, gyro CAN protocol v2), classic and FD, and 5 on one classic bus: what a full bus
// costs. The in-process bus times each frame with its real stuff bits; the simulated electronics
// have a 32-frame transmit queue and lose frames at the source when it is full. The plan check
// (hrg-bench check, worst-case stuffing, 70 %) would refuse the shared classic bus; it is
// bypassed here to see what would happen.
// Prints Markdown tables (kept in docs/measurements/ with the command that made them):
//
//   fixture_throughput_table [--units 1,2,4,8] [--only units|buses]
//
// The table time is the simulated clock's, start to verdict: what the real table would take (the
// table settles, the units are excited, released and captured, at each of the 6 rates). The wall
// and CPU times are this machine's for simulating and recording it all. Positions 1-4 carry
// station-sim-fixture.toml's four units; positions 5-8 the same four truths with their own seeds.
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "app/station_factory.hpp"
#include "hrgbench/bench/sequencer/sequencer.hpp"
#include "hrgbench/config/bench_configs.hpp"
#include "hrgbench/session/session.hpp"

namespace {

using namespace hrgbench;

double CpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

enum class Buses { kSeparate, kOneClassic, kOneFd };

const char* ToString(Buses buses) {
  switch (buses) {
    case Buses::kSeparate:
      return "separate buses (classic)";
    case Buses::kOneClassic:
      return "one bus (classic, 1 Mbit/s)";
    case Buses::kOneFd:
      return "one bus (CAN FD, 1/5 Mbit/s)";
  }
  return "?";
}

struct Row {
  int units = 0;
  std::uint64_t planned = 0;  // samples the complete runs were planned to have
  std::uint64_t gaps = 0;     // sequence gaps (each one or more samples lost)
  int complete_runs = 0;
  double table_s = 0.0;
  double wall_s = 0.0;
  double cpu_s = 0.0;
  std::uint64_t samples = 0;
  std::uint64_t lost = 0;  // sequence gaps + kernel drops over every unit's runs
  int passed = 0;
  double bus_share = 0.0;
};

Row RunFixture(bench::BenchConfigs configs, int units, const std::filesystem::path& work,
               Buses buses = Buses::kSeparate) {
  configs.station.gyro.fd = buses == Buses::kOneFd;
  const std::vector<bench::FixturePosition> file = configs.station.fixture;
  configs.station.fixture.clear();
  for (int i = 0; i < units; ++i) {
    bench::FixturePosition position = file[static_cast<std::size_t>(i) % file.size()];
    position.name = "P" + std::to_string(i + 1);
    position.can_interface = buses == Buses::kSeparate ? "vsim-" + position.name : "vsim-shared";
    position.can_node = buses == Buses::kSeparate ? 0 : i;
    position.index = static_cast<std::size_t>(i);
    position.simulated.seed.reset();  // [simulated]'s + 1000 × index: every unit its own noise
    configs.station.fixture.push_back(position);
  }
  Row row;
  row.units = units;
  row.bus_share = bench::BusiestRunLoad(configs).load.bus_share;
  auto station = app::OpenStation(configs.station);
  if (!station) {
    std::fprintf(stderr, "%s\n", station.error().c_str());
    std::exit(2);
  }
  const bench::BenchHardware& hardware = (*station)->hardware();
  std::vector<bench::UnitSession> sessions;
  for (int i = 0; i < units; ++i) {
    bench::UnitSession unit;
    unit.serial = "TP-" + std::to_string(i + 1);
    unit.dir = work / (std::to_string(units) + "-" + unit.serial);
    unit.simulation = (*station)->simulation(static_cast<std::size_t>(i));
    sessions.push_back(unit);
  }
  bench::RunnerOptions options;
  options.software_version = "fixture_throughput_table";
  const std::int64_t table_start = hardware.clock->NowNs();
  const double cpu_start = CpuSeconds();
  const auto wall_start = std::chrono::steady_clock::now();
  const std::vector<bench::SessionResult> results =
      bench::RunSessions(configs, hardware, sessions, options);
  row.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  row.cpu_s = CpuSeconds() - cpu_start;
  row.table_s = static_cast<double>(hardware.clock->NowNs() - table_start) * 1e-9;
  for (const bench::SessionResult& result : results) {
    row.passed += result.outcome == bench::OutcomeKind::kPass ? 1 : 0;
    session::ReadOptions read;
    read.load_samples = false;
    auto recorded = session::ReadSession(result.dir, read);
    if (!recorded) continue;
    for (const nlohmann::json& run : recorded->document.at("runs")) {
      if (!run.contains("end")) continue;
      const nlohmann::json& end = run.at("end");
      const auto samples = end.value("samples", std::uint64_t{0});
      const nlohmann::json& plan = run.at("plan");
      const auto planned = static_cast<std::uint64_t>(
          plan.value("free_run_s", 0.0) * plan.value("sample_rate_hz", 0.0) + 0.5);
      row.samples += samples;
      row.planned += planned;
      row.complete_runs += run.value("status", std::string()) == "complete" ? 1 : 0;
      row.gaps += end.value("sequence_gaps", std::uint64_t{0});
      row.lost +=
          (planned > samples ? planned - samples : 0) + end.value("kernel_drops", std::uint64_t{0});
    }
  }
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> counts{1, 2, 4, 8};
  std::string only;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::string(argv[i]) == "--only") only = argv[i + 1];
    if (std::string(argv[i]) == "--units") {
      counts.clear();
      std::stringstream list(argv[i + 1]);
      for (std::string n; std::getline(list, n, ',');) counts.push_back(std::stoi(n));
    }
  }
  const std::filesystem::path configs_dir =
      std::filesystem::path(HRGBENCH_SOURCE_DIR) / "bench_configs";
  auto configs = bench::LoadBenchConfigs(configs_dir / "station-sim-fixture.toml",
                                         configs_dir / "sequence-production.toml",
                                         configs_dir / "limits-example.toml");
  if (!configs) {
    std::fprintf(stderr, "%s\n", configs.error().ToString().c_str());
    return 2;
  }
  configs->station.results_url.clear();
  std::random_device rd;
  const std::filesystem::path work =
      std::filesystem::temp_directory_path() / ("hrgbench-fixture-table-" + std::to_string(rd()));
  if (only != "buses") {
    std::printf(
        "| units | table time | units per table-hour | each bus busy | samples | lost | PASS "
        "| wall here | CPU here |\n");
    std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (int units : counts) {
      const Row row = RunFixture(*configs, units, work);
      std::printf("| %d | %.0f s | %.1f | %.1f %% | %llu | %llu | %d/%d | %.1f s | %.1f s |\n",
                  row.units, row.table_s, row.units * 3600.0 / row.table_s, 100.0 * row.bus_share,
                  static_cast<unsigned long long>(row.samples),
                  static_cast<unsigned long long>(row.lost), row.passed, row.units, row.wall_s,
                  row.cpu_s);
      std::fflush(stdout);
      std::filesystem::remove_all(work);
    }
  }
  if (only != "units") {
    std::printf(
        "\n| units × 1 kHz | on | busiest bus planned | complete runs | samples | lost "
        "(gaps) | PASS | wall here |\n");
    std::printf("|---:|---|---:|---:|---:|---:|---:|---:|\n");
    const std::pair<int, Buses> cases[] = {{4, Buses::kSeparate},
                                           {4, Buses::kOneClassic},
                                           {5, Buses::kOneClassic},
                                           {4, Buses::kOneFd}};
    for (const auto& [units, buses] : cases) {
      const Row row = RunFixture(*configs, units, work, buses);
      std::printf("| %d | %s | %.1f %% | %d/%d | %llu | %llu (%llu) | %d/%d | %.1f s |\n", units,
                  ToString(buses), 100.0 * row.bus_share, row.complete_runs, 6 * units,
                  static_cast<unsigned long long>(row.samples),
                  static_cast<unsigned long long>(row.lost),
                  static_cast<unsigned long long>(row.gaps), row.passed, units, row.wall_s);
      std::fflush(stdout);
      std::filesystem::remove_all(work);
    }
  }
  return 0;
}
