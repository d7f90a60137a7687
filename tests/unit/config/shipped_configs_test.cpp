// Every shipped station-*, sequence-* and limits-* file in bench_configs/ loads (STYLE rule 10),
// and together they pass the cross-file checks. sim-*.toml are src/app's (its tests load them).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "hrgbench/config/bench_configs.hpp"

namespace hrgbench::bench {
namespace {

namespace fs = std::filesystem;

const fs::path kConfigDir = fs::path(HRGBENCH_SOURCE_DIR) / "bench_configs";

std::vector<fs::path> Shipped(std::string_view prefix) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(kConfigDir)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with(prefix) && entry.path().extension() == ".toml")
      files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(ShippedConfigs, EveryTomlHasAKnownKind) {
  for (const auto& entry : fs::directory_iterator(kConfigDir)) {
    if (entry.path().extension() != ".toml") continue;
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(name.starts_with("station-") || name.starts_with("sequence-") ||
                name.starts_with("limits-") || name.starts_with("sim-"))
        << name << ": no test would load it (prefix station-, sequence-, limits- or sim-)";
  }
}

TEST(ShippedConfigs, EveryStationLoads) {
  const auto files = Shipped("station-");
  ASSERT_GE(files.size(), 2u);
  for (const fs::path& file : files) {
    auto station = LoadStationConfig(file);
    EXPECT_TRUE(station.has_value()) << (station ? "" : station.error().ToString());
    if (station) {
      EXPECT_EQ(station->sha256_hex.size(), 64u);
    }
  }
}

TEST(ShippedConfigs, EverySequenceLoads) {
  const auto files = Shipped("sequence-");
  ASSERT_GE(files.size(), 2u);
  for (const fs::path& file : files) {
    auto sequence = LoadSequenceConfig(file);
    EXPECT_TRUE(sequence.has_value()) << (sequence ? "" : sequence.error().ToString());
    if (sequence) {
      EXPECT_FALSE(sequence->runs.empty()) << file;
    }
  }
}

TEST(ShippedConfigs, EveryLimitsFileLoads) {
  const auto files = Shipped("limits-");
  ASSERT_GE(files.size(), 1u);
  for (const fs::path& file : files) {
    auto limits = LoadLimitsConfig(file);
    EXPECT_TRUE(limits.has_value()) << (limits ? "" : limits.error().ToString());
  }
}

// Every station with every sequence and every limits file: what `hrg-bench check` would say.
TEST(ShippedConfigs, EveryCombinationPassesTheCrossChecks) {
  for (const fs::path& station : Shipped("station-")) {
    for (const fs::path& sequence : Shipped("sequence-")) {
      for (const fs::path& limits : Shipped("limits-")) {
        auto configs = LoadBenchConfigs(station, sequence, limits);
        EXPECT_TRUE(configs.has_value()) << (configs ? "" : configs.error().ToString());
      }
      auto without_limits = LoadBenchConfigs(station, sequence, "");
      EXPECT_TRUE(without_limits.has_value());
      if (without_limits) {
        EXPECT_TRUE(without_limits->limits.limits.empty());
      }
    }
  }
}

TEST(ShippedConfigs, SimulatedStationIsFasterThanRealTimeAndQuietAboutFaults) {
  auto station = LoadStationConfig(kConfigDir / "station-sim.toml");
  ASSERT_TRUE(station.has_value()) << station.error().ToString();
  EXPECT_EQ(station->kind, StationKind::kSimulated);
  EXPECT_TRUE(station->simulated.faster_than_real_time);
  const SimulatedFaults& f = station->simulated.faults;
  EXPECT_FALSE(f.table_never_stable || f.gyro_never_ready || f.table_fault_after_s ||
               f.table_unresponsive_after_s || f.gyro_stall_after_samples ||
               f.gyro_bus_off_after_samples || f.gyro_drop_every_nth_sample != 0);
}

TEST(ShippedConfigs, ExampleRealStationIsTcpOnCan) {
  auto station = LoadStationConfig(kConfigDir / "station-example-real.toml");
  ASSERT_TRUE(station.has_value()) << station.error().ToString();
  EXPECT_EQ(station->kind, StationKind::kReal);
  EXPECT_EQ(station->gyro.can_interface, "can0");
  EXPECT_EQ(station->table.transport, TableTransport::kTcp);
  EXPECT_FALSE(station->table.host.empty());
  // Elevation 90°: the axis is up.
  EXPECT_NEAR(station->site.axis_enu[2], 1.0, 1e-15);
}

TEST(ShippedConfigs, PaperSequenceIsThePapersExperiment) {
  auto sequence = LoadSequenceConfig(kConfigDir / "sequence-paper.toml");
  ASSERT_TRUE(sequence.has_value()) << sequence.error().ToString();
  ASSERT_EQ(sequence->runs.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    const double k = static_cast<double>(i);  // k - 1 of the paper
    const SequenceRun& run = sequence->runs[i];
    EXPECT_EQ(run.a, 1.0);
    EXPECT_NEAR(run.b, -0.4 + 0.2 * k, 1e-15);
    EXPECT_NEAR(run.theta_rad, std::numbers::pi / 7.0 * k, 1e-15);
    EXPECT_NEAR(run.omega_rad_s, -1e-4 + 5e-5 * k, 1e-19);
    EXPECT_EQ(run.sample_rate_hz, 100u);
    EXPECT_EQ(run.free_run_s, 10.0);
    EXPECT_EQ(run.Samples(), 1000u);
  }
}

TEST(ShippedConfigs, ProductionSequenceIsTheChosenDesign) {
  auto sequence = LoadSequenceConfig(kConfigDir / "sequence-production.toml");
  ASSERT_TRUE(sequence.has_value()) << sequence.error().ToString();
  ASSERT_EQ(sequence->runs.size(), 6u);
  const double omegas[] = {0.1, -0.1, 0.3, -0.3, 1.0, -1.0};
  for (std::size_t k = 0; k < 6; ++k) {
    const SequenceRun& run = sequence->runs[k];
    EXPECT_EQ(run.omega_rad_s, omegas[k]);
    EXPECT_NEAR(run.theta_rad, static_cast<double>(k) * std::numbers::pi / 12.0, 1e-15);
    EXPECT_EQ(run.b, 0.1 * static_cast<double>(k % 3));
    EXPECT_EQ(run.sample_rate_hz, 1000u);
    EXPECT_EQ(run.free_run_s, 100.0);
  }
  EXPECT_EQ(sequence->TotalFreeRunS(), 600.0);
}

// The production design cut into passes a session can stop between: the same six rates and wave
// states, 20 s each then 80 s each, 600 s of free run in all (what the full sequence measures
// when no decision comes), ended once the unit's verdict is decided.
TEST(ShippedConfigs, AdaptiveProductionSequenceIsTheProductionDesignInTwoPasses) {
  auto production = LoadSequenceConfig(kConfigDir / "sequence-production.toml");
  auto adaptive = LoadSequenceConfig(kConfigDir / "sequence-production-adaptive.toml");
  ASSERT_TRUE(production.has_value()) << production.error().ToString();
  ASSERT_TRUE(adaptive.has_value()) << adaptive.error().ToString();
  ASSERT_EQ(adaptive->runs.size(), 12u);
  for (std::size_t i = 0; i < 12; ++i) {
    const SequenceRun& run = adaptive->runs[i];
    const SequenceRun& design = production->runs[i % 6];
    EXPECT_EQ(run.omega_rad_s, design.omega_rad_s) << "run " << i + 1;
    EXPECT_EQ(run.theta_rad, design.theta_rad) << "run " << i + 1;
    EXPECT_EQ(run.b, design.b) << "run " << i + 1;
    EXPECT_EQ(run.a, design.a) << "run " << i + 1;
    EXPECT_EQ(run.sample_rate_hz, design.sample_rate_hz) << "run " << i + 1;
    EXPECT_EQ(run.free_run_s, i < 6 ? 20.0 : 80.0) << "run " << i + 1;
  }
  EXPECT_EQ(adaptive->TotalFreeRunS(), production->TotalFreeRunS());
  EXPECT_TRUE(adaptive->adaptive.stop_when_decided);
  EXPECT_EQ(adaptive->adaptive.min_runs, 2);
  EXPECT_EQ(adaptive->adaptive.look_interval_s, 5.0);
  // None within the 20 s runs (a look within a run waits until it is as long as the shortest run
  // made), 12 within each 80 s one (20 … 75 s), one after each of runs 2 … 11.
  EXPECT_EQ(adaptive->InterimLookFractions().size(), 6u * 12u + 10u);
  // Everything else as production's: settling, warm-up, drift and capture criteria.
  EXPECT_EQ(adaptive->warmup.min_s, production->warmup.min_s);
  EXPECT_EQ(adaptive->settle.rate_tolerance_rad_s, production->settle.rate_tolerance_rad_s);
  EXPECT_EQ(adaptive->prompts.size(), production->prompts.size());
}

}  // namespace
}  // namespace hrgbench::bench
