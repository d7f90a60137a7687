// The plan's load on the gyro's CAN bus (CheckBenchConfigs, hw/gyro_link_load.hpp): the shipped
// stations carry the shipped sequences; a plan above 70 % is refused naming the run's key, the
// bus, the load and what would fit; the simulated station is judged at its in-process bus's rates.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "hrgbench/config/bench_configs.hpp"
#include "hrgbench/config/sequence_config.hpp"
#include "hrgbench/config/station_config.hpp"

namespace hrgbench::bench {
namespace {

std::string RealStation(const std::string& gyro_keys) {
  return "[station]\nname = \"line-3\"\nkind = \"real\"\n[site]\nlatitude_deg = 45.0\n"
         "axis_enu = [0.0, 0.0, 1.0]\n[gyro]\ncan_interface = \"can1\"\n" +
         gyro_keys + "[table]\ntransport = \"tcp\"\nhost = \"10.0.0.2\"\n";
}

BenchConfigs Production(const std::string& station_text) {
  BenchConfigs configs;
  auto station = ParseStationConfig(station_text, "s.toml");
  EXPECT_TRUE(station.has_value()) << station.error().ToString();
  if (station) configs.station = *station;
  auto sequence = LoadSequenceConfig(std::string(HRGBENCH_SOURCE_DIR) +
                                     "/bench_configs/sequence-production.toml");
  EXPECT_TRUE(sequence.has_value()) << sequence.error().ToString();
  if (sequence) configs.sequence = *sequence;
  return configs;
}

TEST(BusLoadPlan, ProductionAtOneKilohertzOnAOneMegabitBus) {
  const BenchConfigs configs = Production(RealStation(""));
  ASSERT_TRUE(CheckBenchConfigs(configs).has_value());
  const PlannedBusLoad bus = BusiestRunLoad(configs);
  EXPECT_EQ(bus.sample_rate_hz, 1000u);
  // 2000 sample + 200 reference-phase + 10 status frames of 135 µs (worst-case stuffing).
  EXPECT_NEAR(bus.load.bus_share, 2210 * 135e-6, 1e-12);
  EXPECT_EQ(bus.bus, "can1 at 1000 kbit/s");
  EXPECT_EQ(Percent(bus.load.bus_share), "29.8 %");
}

TEST(BusLoadPlan, ASlowBusIsRefusedWithWhatWouldFit) {
  // At 250 kbit/s a frame takes 540 µs: 1 kHz would be 2210 × 540 µs = 119.3 %. 70 % holds
  // 0.70 / 540 µs = 1296 frames/s, 10 of them status: (1286 / 2.2) = 584 samples/s.
  const BenchConfigs configs = Production(RealStation("bitrate = 250000\n"));
  auto ok = CheckBenchConfigs(configs);
  ASSERT_FALSE(ok.has_value());
  EXPECT_EQ(ok.error().key, "runs[0].sample_rate_hz");
  EXPECT_EQ(ok.error().value, "1000");
  EXPECT_NE(ok.error().file.string().find("sequence-production.toml"), std::string::npos);
  const std::string& message = ok.error().message;
  EXPECT_NE(message.find("can1 at 250 kbit/s"), std::string::npos) << message;
  EXPECT_NE(message.find("119.3 % busy"), std::string::npos) << message;
  EXPECT_NE(message.find("at most 584 samples/s fit"), std::string::npos) << message;
  EXPECT_NE(message.find("gyro.fd = true"), std::string::npos) << message;

  // CAN FD at the same nominal rate with a 2 Mbit/s data phase: 200 FD frames (33 bits at 250
  // kbit/s + 679 bits at 2 Mbit/s = 132 + 339.5 µs) + 210 classic frames of 540 µs = 20.8 %.
  const BenchConfigs fd = Production(RealStation("bitrate = 250000\nfd = true\n"));
  ASSERT_TRUE(CheckBenchConfigs(fd).has_value()) << CheckBenchConfigs(fd).error().ToString();
  EXPECT_NEAR(BusiestRunLoad(fd).load.bus_share, 200 * 471.5e-6 + 210 * 540e-6, 1e-9);
}

// A real station whose positions share can1 (nodes 1, 2, ...) and, optionally, one unit on can2.
std::string SharedBusStation(int units_on_can1) {
  std::string text = RealStation("");
  const std::string gyro_interface = "can_interface = \"can1\"\n";
  text.replace(text.find(gyro_interface), gyro_interface.size(), "");
  const char* names[] = {"A", "B", "C", "D"};
  for (int i = 0; i < units_on_can1; ++i)
    text += std::string("[[fixture]]\nposition = \"") + names[i] +
            "\"\ncan_interface = \"can1\"\ncan_node = " + std::to_string(i + 1) + "\n";
  return text + "[[fixture]]\nposition = \"E\"\ncan_interface = \"can2\"\n";
}

TEST(BusLoadPlan, TwoUnitsOnOneBusAtOneKilohertzFit) {
  // Both units stream at once: 2 × 2210 frames/s × 135 µs = 59.67 % of can1.
  const BenchConfigs configs = Production(SharedBusStation(2));
  ASSERT_TRUE(CheckBenchConfigs(configs).has_value())
      << CheckBenchConfigs(configs).error().ToString();
  const PlannedBusLoad bus = BusiestRunLoad(configs);
  EXPECT_EQ(bus.units, 2u);
  EXPECT_NEAR(bus.load.bus_share, 2 * 2210 * 135e-6, 1e-12);
  EXPECT_NEAR(bus.load.frames_per_s, 2 * 2210, 1e-9);
  EXPECT_EQ(bus.bus, "can1 (2 units: A, B) at 1000 kbit/s");
  // Each bus on its own: can1 with A and B, can2 with E alone at one unit's 29.8 %.
  const std::vector<PlannedBusLoad> each = EachBusLoad(configs);
  ASSERT_EQ(each.size(), 2u);
  EXPECT_EQ(each[0].bus, "can1");
  EXPECT_EQ(each[0].positions, (std::vector<std::string>{"A", "B"}));
  EXPECT_NEAR(each[0].load.bus_share, 2 * 2210 * 135e-6, 1e-12);
  EXPECT_EQ(each[1].bus, "can2");
  EXPECT_EQ(each[1].positions, (std::vector<std::string>{"E"}));
  EXPECT_NEAR(each[1].load.bus_share, 2210 * 135e-6, 1e-12);
}

TEST(BusLoadPlan, UnitsThatOverloadTheirSharedBusAreRefused) {
  // Three units at 1 kHz: 3 × 29.835 % = 89.5 %. Per unit 70 % / 3 = 23.33 % = 1728.4 frames of
  // 135 µs per second, 10 of them status: 1718.4 / 2.2 frames per sample = 781 samples/s.
  const BenchConfigs three = Production(SharedBusStation(3));
  auto refused = CheckBenchConfigs(three);
  ASSERT_FALSE(refused.has_value());
  EXPECT_EQ(refused.error().key, "runs[0].sample_rate_hz");
  const std::string& message = refused.error().message;
  EXPECT_NE(message.find("the bus can1 (3 units: A, B, C) at 1000 kbit/s would be 89.5 % busy"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("at most 781 samples/s per unit fit"), std::string::npos) << message;
  EXPECT_NE(message.find("fewer units on that bus"), std::string::npos) << message;

  // Two units at 2 kHz (the classic maximum, 54 % each alone): 2 × 4410 × 135 µs = 119.1 %.
  // Per unit 35 % = 2592.6 frames/s: (2592.6 − 10) / 2.2 = 1173 samples/s.
  BenchConfigs two = Production(SharedBusStation(2));
  for (SequenceRun& run : two.sequence.runs) run.sample_rate_hz = 2000;
  refused = CheckBenchConfigs(two);
  ASSERT_FALSE(refused.has_value());
  EXPECT_NE(refused.error().message.find("119.1 % busy"), std::string::npos)
      << refused.error().message;
  EXPECT_NE(refused.error().message.find("at most 1173 samples/s per unit fit"), std::string::npos)
      << refused.error().message;
}

TEST(BusLoadPlan, TheSimulatedStationIsJudgedAtItsBussRates) {
  const BenchConfigs configs = Production(
      "[station]\nname = \"sim\"\nkind = \"simulated\"\n[site]\nlatitude_deg = 45.0\n"
      "axis_enu = [0.0, 0.0, 1.0]\n[gyro]\nfd = true\n[simulated]\n");
  EXPECT_EQ(configs.station.gyro.bitrate, 1'000'000);
  EXPECT_EQ(configs.station.gyro.data_bitrate, 5'000'000);
  EXPECT_EQ(BusiestRunLoad(configs).bus, "the simulated bus at 1000 kbit/s, FD data 5000 kbit/s");
}

// An interim decision of [adaptive] less sure than the final one is refused, naming the sequence's
// key, its value and the limits file's k.
TEST(AdaptivePlan, AnInterimCoverageFactorBelowTheLimitsOneIsRefused) {
  BenchConfigs configs = Production(RealStation(""));
  configs.limits.file = "limits.toml";
  configs.limits.decision.coverage_factor = 2.5;
  configs.sequence.adaptive.stop_when_decided = true;
  configs.sequence.adaptive.interim_coverage_factor = 2.0;
  auto refused = CheckBenchConfigs(configs);
  ASSERT_FALSE(refused.has_value());
  EXPECT_EQ(refused.error().key, "adaptive.interim_coverage_factor") << refused.error().ToString();
  EXPECT_EQ(refused.error().value, "2") << refused.error().ToString();
  EXPECT_NE(refused.error().message.find("k = 2.5 of limits.toml"), std::string::npos)
      << refused.error().ToString();
  configs.sequence.adaptive.interim_coverage_factor = 2.5;
  EXPECT_TRUE(CheckBenchConfigs(configs).has_value())
      << CheckBenchConfigs(configs).error().ToString();
}

}  // namespace
}  // namespace hrgbench::bench
