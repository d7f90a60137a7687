// Every failure mode of the in-process simulated station, reached through the hw interfaces as
// the bench meets them: table never stable, table fault mid-run, table timeouts, unresponsive
// table, lost connection; gyro stall, bus-off, never ready, dropped frames, fault bits, silence.

#include <gtest/gtest.h>

#include <numbers>

#include "sim/simulated_station.hpp"
#include "station_driver.hpp"

namespace hrgbench::testing {
namespace {

using drivers::sim_station::SimulatedStation;
using drivers::sim_station::SimulatedStationOptions;
using hw::GyroErrorCode;
using hw::GyroReadStatus;
using hw::RateTableErrorCode;

const hw::WaveState kWave{1.0, 0.2, 0.3};

std::unique_ptr<SimulatedStation> MakeStation(const SimulatedStationOptions& options) {
  auto station = SimulatedStation::Create(options);
  EXPECT_TRUE(station.has_value()) << (station ? "" : station.error());
  if (!station) return nullptr;
  EXPECT_TRUE((*station)->table().Connect().has_value());
  return std::move(*station);
}

// Table at rate and the gyro in free run; returns t0.
std::int64_t StartRun(SimulatedStation& station, double omega_rad_s) {
  EXPECT_TRUE(station.table().SetRate(omega_rad_s).has_value());
  EXPECT_TRUE(station.table().WaitUntilStable(TestCriteria()).has_value());
  EXPECT_TRUE(station.gyro().Configure({1000}).has_value());
  EXPECT_TRUE(station.gyro().Excite(kWave).has_value());
  EXPECT_TRUE(station.gyro().WaitReady(2'000'000'000).has_value());
  auto t0 = station.gyro().Release();
  EXPECT_TRUE(t0.has_value());
  return t0.value_or(0);
}

TEST(SimStationFaultsTest, TableNeverStable) {
  SimulatedStationOptions options;
  options.table.faults.never_stable = true;
  auto station = MakeStation(options);
  ASSERT_NE(station, nullptr);
  ASSERT_TRUE(station->table().SetRate(0.5).has_value());
  const auto stable = station->table().WaitUntilStable(TestCriteria());
  ASSERT_FALSE(stable.has_value());
  EXPECT_EQ(stable.error().code, RateTableErrorCode::kNotStable);
  EXPECT_GE(station->clock().NowNs(), 10'000'000'000);  // the whole timeout, in simulated time
  station->table().SafeStop();
}

TEST(SimStationFaultsTest, TableFaultsMidRun) {
  SimulatedStationOptions options;
  options.table.faults.fault_after_s = 6.0;  // ~4 s into the free run
  auto station = MakeStation(options);
  ASSERT_NE(station, nullptr);
  StartRun(*station, 0.5);
  FreeRun run;
  for (int chunk = 1; chunk <= 16; ++chunk) {  // the gyro keeps streaming; Ω falls away
    ReadSamples(station->gyro(), 500u * chunk, &run);
    ASSERT_TRUE(station->table().Heartbeat().has_value());  // as the sequencer does
  }
  EXPECT_EQ(run.samples.size(), 8'000u);
  EXPECT_LT(station->in_process_table().SenseTrueRateRadS(), 0.1);
  const auto status = station->table().ReadStatus();
  ASSERT_TRUE(status.has_value());
  EXPECT_TRUE(status->fault);
  EXPECT_EQ(status->fault_code, static_cast<std::uint16_t>(hw::RateTableFault::kDrive));
  EXPECT_EQ(station->table().SetRate(0.5).error().code, RateTableErrorCode::kFaulted);
  EXPECT_EQ(station->table().WaitUntilStable(TestCriteria()).error().code,
            RateTableErrorCode::kFaulted);
  EXPECT_TRUE(station->gyro().Stop().has_value());
  station->table().SafeStop();
}

TEST(SimStationFaultsTest, TableTimeoutsThenRecovers) {
  auto station = MakeStation({});
  ASSERT_NE(station, nullptr);
  station->in_process_table().FailNextCalls(2, RateTableErrorCode::kTimeout);
  EXPECT_EQ(station->table().SetRate(0.2).error().code, RateTableErrorCode::kTimeout);
  EXPECT_EQ(station->table().ReadStatus().error().code, RateTableErrorCode::kTimeout);
  EXPECT_EQ(station->clock().NowNs(), 800'000'000);  // 2 calls x 2 attempts x 200 ms
  EXPECT_TRUE(station->table().SetRate(0.2).has_value());
  EXPECT_EQ(station->in_process_table().counters().timeouts, 2u);
}

TEST(SimStationFaultsTest, TableUnresponsiveMidSession) {
  SimulatedStationOptions options;
  options.table.faults.unresponsive_after_s = 3.0;
  auto station = MakeStation(options);
  ASSERT_NE(station, nullptr);
  StartRun(*station, 0.3);
  FreeRun run;
  ReadSamples(station->gyro(), 3'000, &run);
  EXPECT_EQ(station->table().Heartbeat().error().code, RateTableErrorCode::kTimeout);
  const std::int64_t before = station->clock().NowNs();
  station->table().SafeStop();  // bounded although the table cannot be reached
  EXPECT_LE(station->clock().NowNs() - before, 1'200'000'000);
  EXPECT_TRUE(station->gyro().Stop().has_value());
}

TEST(SimStationFaultsTest, TableConnectionLost) {
  auto station = MakeStation({});
  ASSERT_NE(station, nullptr);
  station->in_process_table().FailNextCalls(1, RateTableErrorCode::kConnectionLost);
  EXPECT_EQ(station->table().ReadStatus().error().code, RateTableErrorCode::kConnectionLost);
  EXPECT_EQ(station->table().SetRate(0.1).error().code, RateTableErrorCode::kNotConnected);
  ASSERT_TRUE(station->table().Connect().has_value());
  EXPECT_TRUE(station->table().SetRate(0.1).has_value());
}

TEST(SimStationFaultsTest, GyroStopsStreaming) {
  SimulatedStationOptions options;
  options.units[0].gyro.faults.stall_after_samples = 3'000;
  auto station = MakeStation(options);
  ASSERT_NE(station, nullptr);
  StartRun(*station, 0.3);
  FreeRun run;
  ReadSamples(station->gyro(), 10'000, &run);
  EXPECT_EQ(run.samples.size(), 3'000u);
  EXPECT_EQ(run.last_read, GyroReadStatus::kTimeout);
  EXPECT_GE(station->gyro().Counters().timeouts, 1u);
  EXPECT_TRUE(station->gyro().Stop().has_value());
  station->table().SafeStop();
}

TEST(SimStationFaultsTest, GyroBusGoesBusOff) {
  SimulatedStationOptions options;
  options.units[0].gyro.faults.bus_off_after_samples = 2'000;
  auto station = MakeStation(options);
  ASSERT_NE(station, nullptr);
  StartRun(*station, 0.3);
  FreeRun run;
  ReadSamples(station->gyro(), 10'000, &run);
  EXPECT_EQ(run.samples.size(), 2'000u);
  EXPECT_EQ(run.last_read, GyroReadStatus::kBusOff);
  EXPECT_EQ(station->gyro().State(), hw::GyroMode::kFaulted);
  EXPECT_GE(station->gyro().Counters().bus_errors, 1u);
  station->table().SafeStop();  // the table is not on the CAN bus: still reachable
  EXPECT_EQ(station->in_process_table().target_rate_rad_s(), 0.0);
}

TEST(SimStationFaultsTest, GyroNeverReady) {
  SimulatedStationOptions options;
  options.units[0].gyro.faults.never_ready = true;
  auto station = MakeStation(options);
  ASSERT_NE(station, nullptr);
  ASSERT_TRUE(station->gyro().Configure({1000}).has_value());
  ASSERT_TRUE(station->gyro().Excite(kWave).has_value());
  const auto ready = station->gyro().WaitReady(2'000'000'000);
  ASSERT_FALSE(ready.has_value());
  EXPECT_EQ(ready.error().code, GyroErrorCode::kTimeout);
  EXPECT_EQ(station->gyro().State(), hw::GyroMode::kExciting);
}

TEST(SimStationFaultsTest, GyroDropsSampleFramesAndTheGapsAreCounted) {
  SimulatedStationOptions options;
  options.units[0].gyro.faults.drop_every_nth_frame = 100;
  auto station = MakeStation(options);
  ASSERT_NE(station, nullptr);
  const std::int64_t t0 = StartRun(*station, 0.3);
  FreeRun run;
  run.t0_ns = t0;
  ReadSamples(station->gyro(), 9'900, &run);
  const hw::GyroCounters c = station->gyro().Counters();
  EXPECT_GE(c.sequence_gaps, 90u);  // one lost half-sample frame loses its sample
  EXPECT_EQ(c.samples_lost, c.sequence_gaps);
  for (std::size_t k = 1; k < run.samples.size(); ++k) {
    ASSERT_GT(run.samples[k].seq, run.samples[k - 1].seq);  // in order, gaps never filled
    ASSERT_EQ(run.samples[k].t_ns, t0 + std::int64_t{run.samples[k].seq} * 1'000'000);
  }
}

TEST(SimStationFaultsTest, GyroReportsAFaultWhileExciting) {
  auto station = MakeStation({});
  ASSERT_NE(station, nullptr);
  ASSERT_TRUE(station->gyro().Configure({1000}).has_value());
  ASSERT_TRUE(station->gyro().Excite(kWave).has_value());
  ASSERT_TRUE(station->InjectGyroFaults(
      [](drivers::sim::GyroSimFaults& f) { f.fault_bits = hw::gyro_fault::kOverTemperature; }));
  const auto ready = station->gyro().WaitReady(2'000'000'000);
  ASSERT_FALSE(ready.has_value());
  EXPECT_EQ(ready.error().code, GyroErrorCode::kFaulted);
  EXPECT_EQ(station->gyro().State(), hw::GyroMode::kFaulted);
  EXPECT_TRUE(station->gyro().Stop().has_value());  // the way out
  EXPECT_EQ(station->gyro().State(), hw::GyroMode::kStopped);
}

TEST(SimStationFaultsTest, GyroSilentCommandsTimeOutAfterTheRetries) {
  SimulatedStationOptions options;
  options.units[0].gyro.faults.no_reply = true;
  auto station = MakeStation(options);
  ASSERT_NE(station, nullptr);
  const auto configured = station->gyro().Configure({1000});
  ASSERT_FALSE(configured.has_value());
  EXPECT_EQ(configured.error().code, GyroErrorCode::kTimeout);
  EXPECT_EQ(station->gyro().Counters().command_retries, 2u);
  EXPECT_EQ(station->clock().NowNs(), 150'000'000);  // 3 attempts x 50 ms, simulated
}

}  // namespace
}  // namespace hrgbench::testing
