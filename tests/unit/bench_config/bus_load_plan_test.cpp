// The plan's load on the gyro's CAN bus (CheckBenchConfigs, hw/gyro_link_load.hpp): the shipped
// stations carry the shipped sequences; a plan above 70 % is refused naming the run's key, the
// bus, the load and what would fit; the simulated station is judged at its in-process bus's rates.

#include <gtest/gtest.h>

#include <string>

#include "hrgbench/bench/bench_configs.hpp"
#include "hrgbench/bench/sequence_config.hpp"
#include "hrgbench/bench/station_config.hpp"

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

TEST(BusLoadPlan, TheSimulatedStationIsJudgedAtItsBussRates) {
  const BenchConfigs configs = Production(
      "[station]\nname = \"sim\"\nkind = \"simulated\"\n[site]\nlatitude_deg = 45.0\n"
      "axis_enu = [0.0, 0.0, 1.0]\n[gyro]\nfd = true\n[simulated]\n");
  EXPECT_EQ(configs.station.gyro.bitrate, 1'000'000);
  EXPECT_EQ(configs.station.gyro.data_bitrate, 5'000'000);
  EXPECT_EQ(BusiestRunLoad(configs).bus, "the simulated bus at 1000 kbit/s, FD data 5000 kbit/s");
}

}  // namespace
}  // namespace hrgbench::bench
