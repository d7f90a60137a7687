// The real driver against the simulated table over Modbus TCP on 127.0.0.1: normal operation,
// software limits, watchdog, e-stop, SafeStop.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "modbus_rate_table/modbus_rate_table.hpp"
#include "sim_table_fixture.hpp"

namespace hrgbench::drivers::modbus_rate_table {
namespace {

using hw::RateTableErrorCode;
using testing::SimTable;
using Seconds = std::chrono::duration<double>;

class ModbusTableTcp : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(sim_.Start(), "") << "no simulator server"; }
  SimTable sim_;
  hw::SteadyClock clock_;
};

TEST_F(ModbusTableTcp, SetRateBecomesStable) {
  ModbusRateTable table(sim_.DriverConfig(), clock_);
  ASSERT_TRUE(table.Connect()) << "connect";
  EXPECT_EQ(table.state(), TableLinkState::kConnected);
  EXPECT_EQ(sim_.physics().accel_limit_rad_s2(), 2.0);  // written and read back at Connect
  EXPECT_EQ(sim_.physics().watchdog_ms(), 1000);

  ASSERT_TRUE(table.SetRate(0.5));
  const auto stable = table.WaitUntilStable(
      {.tolerance_rad_s = 2e-3, .dwell_s = 0.2, .timeout_s = 10.0, .poll_period_s = 0.02});
  ASSERT_TRUE(stable) << stable.error().ToString();
  EXPECT_NEAR(stable->measured_rate_rad_s, 0.5, 2e-3);
  EXPECT_EQ(stable->commanded_rate_rad_s, 0.5);
  EXPECT_EQ(stable->mode, hw::RateTableMode::kRate);
  EXPECT_TRUE(stable->rate_stable);
  EXPECT_NEAR(sim_.physics().TrueRateRadS(), 0.5, 2e-3);

  ASSERT_TRUE(table.Stop());
  const auto stopped = table.WaitUntilStable(
      {.tolerance_rad_s = 2e-3, .dwell_s = 0.1, .timeout_s = 1.0, .poll_period_s = 0.02});
  // Idle mode has no "at rate" bit: the table is stopped, not stable at a rate.
  ASSERT_FALSE(stopped);
  EXPECT_EQ(stopped.error().code, RateTableErrorCode::kNotStable);
  EXPECT_NEAR(sim_.physics().TrueRateRadS(), 0.0, 2e-3);

  const auto c = table.counters();
  EXPECT_EQ(c.timeouts, 0u);
  EXPECT_EQ(c.exception_replies, 0u);
  EXPECT_EQ(c.bad_replies, 0u);
  EXPECT_GT(c.heartbeats, 0u);  // the wait lasted several heartbeat periods
}

TEST_F(ModbusTableTcp, SoftwareLimitsRejectBeforeSending) {
  auto config = sim_.DriverConfig();
  config.limits.max_rate_rad_s = 1.0;
  ModbusRateTable table(config, clock_);
  ASSERT_TRUE(table.Connect());
  const auto requests_before = sim_.server().counters().requests;
  auto r = table.SetRate(1.5);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, RateTableErrorCode::kLimitExceeded);
  EXPECT_NE(r.error().message.find("max_rate_rad_s"), std::string::npos);
  r = table.SetAccelerationLimit(100.0);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, RateTableErrorCode::kLimitExceeded);
  EXPECT_EQ(sim_.server().counters().requests, requests_before);  // nothing was sent
  EXPECT_EQ(table.counters().limit_rejections, 2u);
  EXPECT_TRUE(table.SetAccelerationLimit(4.0));
  EXPECT_EQ(sim_.physics().accel_limit_rad_s2(), 4.0);
}

TEST_F(ModbusTableTcp, CallsBeforeConnectAreRefused) {
  ModbusRateTable table(sim_.DriverConfig(), clock_);
  auto r = table.SetRate(0.1);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, RateTableErrorCode::kNotConnected);
  EXPECT_EQ(sim_.server().counters().requests, 0u);
}

TEST_F(ModbusTableTcp, WatchdogStopsTheTableWhenHeartbeatsStop) {
  auto config = sim_.DriverConfig();
  config.watchdog_timeout_ms = 300;
  config.heartbeat_period_ms = 100;
  ModbusRateTable table(config, clock_);
  ASSERT_TRUE(table.Connect());
  ASSERT_TRUE(table.SetRate(0.2));
  // Heartbeats flow while the driver is used...
  for (int i = 0; i < 10; ++i) {
    ASSERT_TRUE(table.ReadStatus());
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_FALSE(sim_.physics().Status().fault);
  // ...and stop when the owner goes quiet for longer than the watchdog.
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  const auto s = table.ReadStatus();
  ASSERT_TRUE(s) << s.error().ToString();
  EXPECT_TRUE(s->fault);
  EXPECT_EQ(s->fault_code, static_cast<std::uint16_t>(hw::RateTableFault::kWatchdog));
  EXPECT_EQ(s->mode, hw::RateTableMode::kIdle);
  EXPECT_EQ(table.state(), TableLinkState::kFaulted);
  const auto refused = table.SetRate(0.2);
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().code, RateTableErrorCode::kFaulted);

  ASSERT_TRUE(table.ResetFault());
  EXPECT_EQ(table.state(), TableLinkState::kConnected);
  EXPECT_TRUE(table.SetRate(0.2));
}

TEST_F(ModbusTableTcp, EStopIsAFaultStatus) {
  ModbusRateTable table(sim_.DriverConfig(), clock_);
  ASSERT_TRUE(table.Connect());
  ASSERT_TRUE(table.SetRate(0.3));
  sim_.physics().SetEStop(true);
  const auto s = table.ReadStatus();
  ASSERT_TRUE(s) << s.error().ToString();  // a fault is a status, not a transport error
  EXPECT_TRUE(s->estop);
  EXPECT_TRUE(s->fault);
  EXPECT_EQ(s->fault_code, static_cast<std::uint16_t>(hw::RateTableFault::kEStop));
  EXPECT_EQ(table.state(), TableLinkState::kFaulted);
  const auto waited = table.WaitUntilStable({.timeout_s = 5.0});
  ASSERT_FALSE(waited);
  EXPECT_EQ(waited.error().code, RateTableErrorCode::kFaulted);
  EXPECT_NE(waited.error().message.find("e-stop"), std::string::npos) << waited.error().message;
  // The fault stays while the e-stop is pressed.
  ASSERT_TRUE(table.ResetFault());
  EXPECT_EQ(table.state(), TableLinkState::kFaulted);
  sim_.physics().SetEStop(false);
  ASSERT_TRUE(table.ResetFault());
  EXPECT_EQ(table.state(), TableLinkState::kConnected);
}

TEST_F(ModbusTableTcp, SafeStopCommandsZeroRate) {
  ModbusRateTable table(sim_.DriverConfig(), clock_);
  ASSERT_TRUE(table.Connect());
  ASSERT_TRUE(table.SetRate(0.4));
  table.SafeStop();
  const auto s = sim_.physics().Status();
  EXPECT_EQ(s.mode, hw::RateTableMode::kIdle);
  EXPECT_EQ(s.commanded_rate_rad_s, 0.0);
}

TEST_F(ModbusTableTcp, SafeStopAfterLostConnectionReturnsWithinItsBound) {
  auto config = sim_.DriverConfig();
  config.safe_stop_budget_ms = 500;
  ModbusRateTable table(config, clock_);
  ASSERT_TRUE(table.Connect());
  ASSERT_TRUE(table.SetRate(0.4));
  sim_.Stop();  // the table's controller vanishes
  const auto start = std::chrono::steady_clock::now();
  table.SafeStop();
  const double took_s = Seconds(std::chrono::steady_clock::now() - start).count();
  // Documented bound: safe_stop_budget_ms + response_timeout_ms; generous slack for a busy CI.
  EXPECT_LT(took_s, 0.5 + 0.2 + 1.0);
  EXPECT_GE(table.counters().reconnects, 1u);
  const auto r = table.ReadStatus();
  ASSERT_FALSE(r);
  EXPECT_TRUE(r.error().code == RateTableErrorCode::kConnectionLost ||
              r.error().code == RateTableErrorCode::kNotConnected)
      << r.error().ToString();
}

TEST(ModbusTableConnect, NoServerIsABoundedConnectFailure) {
  hw::SteadyClock clock;
  ModbusRateTableConfig config;
  config.port = 1;  // nothing listens on tcpmux
  config.connect_attempts = 2;
  config.reconnect_backoff_ms = 50;
  ModbusRateTable table(config, clock);
  const auto start = std::chrono::steady_clock::now();
  const auto r = table.Connect();
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, hw::RateTableErrorCode::kConnectFailed);
  EXPECT_LT(Seconds(std::chrono::steady_clock::now() - start).count(), 3.0);
  EXPECT_EQ(table.state(), TableLinkState::kDisconnected);
}

}  // namespace
}  // namespace hrgbench::drivers::modbus_rate_table
