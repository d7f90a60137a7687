// InProcessRateTable on a TablePhysics and an auto-advancing ManualClock (a sleep is an instant
// jump): the real driver's semantics (limits first, stable decision, state machine, heartbeat,
// SafeStop) and every injected failure.

#include "sim/in_process_rate_table.hpp"

#include <gtest/gtest.h>

namespace hrgbench::drivers::sim_station {
namespace {

using hw::RateTableErrorCode;

constexpr std::int64_t kNsPerS = 1'000'000'000;

struct Rig {
  explicit Rig(InProcessRateTableConfig config = {}, sim::TablePhysicsOptions physics = {})
      : physics_model(physics, clock), table(config, physics_model, clock) {}
  hw::ManualClock clock{0, /*auto_advance=*/true};
  sim::TablePhysics physics_model;
  InProcessRateTable table;
};

hw::StableCriteria Criteria(double timeout_s = 10.0) {
  hw::StableCriteria c;
  c.tolerance_rad_s = 1e-3;
  c.dwell_s = 0.5;
  c.timeout_s = timeout_s;
  c.poll_period_s = 0.05;
  return c;
}

TEST(InProcessRateTableTest, NotConnectedUntilConnectWhichWritesAndReadsBack) {
  InProcessRateTableConfig config;
  config.accel_limit_rad_s2 = 2.0;
  config.watchdog_timeout_ms = 2000;
  Rig rig(config);
  EXPECT_EQ(rig.table.SetRate(0.1).error().code, RateTableErrorCode::kNotConnected);
  EXPECT_EQ(rig.table.ReadStatus().error().code, RateTableErrorCode::kNotConnected);
  ASSERT_TRUE(rig.table.Connect().has_value());
  EXPECT_EQ(rig.table.state(), TableLinkState::kConnected);
  EXPECT_EQ(rig.physics_model.accel_limit_rad_s2(), 2.0);
  EXPECT_EQ(rig.physics_model.watchdog_ms(), 2000);
}

TEST(InProcessRateTableTest, InvalidConfigIsRefusedAtConnect) {
  InProcessRateTableConfig config;
  config.accel_limit_rad_s2 = 50.0;  // above the software limit of 5
  Rig rig(config);
  const auto connected = rig.table.Connect();
  ASSERT_FALSE(connected.has_value());
  EXPECT_EQ(connected.error().code, RateTableErrorCode::kInvalidConfig);
  EXPECT_NE(connected.error().message.find("accel_limit_rad_s2"), std::string::npos);
}

TEST(InProcessRateTableTest, SoftwareLimitsAreCheckedBeforeCommanding) {
  Rig rig;
  ASSERT_TRUE(rig.table.Connect().has_value());
  const auto set = rig.table.SetRate(10.5);
  ASSERT_FALSE(set.has_value());
  EXPECT_EQ(set.error().code, RateTableErrorCode::kLimitExceeded);
  EXPECT_EQ(rig.table.SetAccelerationLimit(6.0).error().code, RateTableErrorCode::kLimitExceeded);
  EXPECT_EQ(rig.physics_model.Status().commanded_rate_rad_s, 0.0);  // nothing commanded
  EXPECT_EQ(rig.table.counters().limit_rejections, 2u);
  EXPECT_EQ(rig.table.counters().calls, 1u);  // only Connect reached the table
}

TEST(InProcessRateTableTest, HardwareLimitIsTheTablesRefusal) {
  sim::TablePhysicsOptions physics;
  physics.max_rate_rad_s = 2.0;  // tighter than the software limit
  Rig rig({}, physics);
  ASSERT_TRUE(rig.table.Connect().has_value());
  EXPECT_EQ(rig.table.SetRate(3.0).error().code, RateTableErrorCode::kExceptionReply);
  EXPECT_EQ(rig.table.counters().refusals, 1u);
}

TEST(InProcessRateTableTest, WaitUntilStableReachesTheRateAfterRampAndDwell) {
  Rig rig;
  ASSERT_TRUE(rig.table.Connect().has_value());
  ASSERT_TRUE(rig.table.SetRate(0.5).has_value());
  const std::int64_t start = rig.clock.NowNs();
  const auto stable = rig.table.WaitUntilStable(Criteria());
  ASSERT_TRUE(stable.has_value()) << stable.error().ToString();
  EXPECT_NEAR(stable->measured_rate_rad_s, 0.5, 1e-3);
  EXPECT_TRUE(stable->rate_stable);
  // Ramp at 1 rad/s^2 (0.5 s) + the table's own hold (0.2 s) + our dwell (0.5 s).
  EXPECT_GE(rig.clock.NowNs() - start, 12 * kNsPerS / 10);
  EXPECT_LT(rig.clock.NowNs() - start, 2 * kNsPerS);
  EXPECT_NEAR(rig.table.SenseTrueRateRadS(), 0.5, 1e-6);
}

TEST(InProcessRateTableTest, CallsKeepTheWatchdogFedAndSilenceTripsIt) {
  Rig rig;
  ASSERT_TRUE(rig.table.Connect().has_value());
  ASSERT_TRUE(rig.table.SetRate(0.2).has_value());
  // 5 s of polling, five times the 1 s watchdog: every poll heartbeats when due.
  auto waited = rig.table.WaitUntilStable(Criteria());
  ASSERT_TRUE(waited.has_value());
  for (int i = 0; i < 50; ++i) {
    rig.clock.SleepForNs(kNsPerS / 10);
    ASSERT_TRUE(rig.table.ReadStatus().has_value());
  }
  EXPECT_FALSE(rig.table.ReadStatus()->fault);
  EXPECT_GE(rig.table.counters().heartbeats, 20u);
  rig.clock.SleepForNs(2 * kNsPerS);  // the owner went silent
  const auto status = rig.table.ReadStatus();
  ASSERT_TRUE(status.has_value());
  EXPECT_TRUE(status->fault);
  EXPECT_EQ(status->fault_code, static_cast<std::uint16_t>(hw::RateTableFault::kWatchdog));
  EXPECT_EQ(rig.table.state(), TableLinkState::kFaulted);
}

TEST(InProcessRateTableTest, NeverStableTimesOut) {
  InProcessRateTableConfig config;
  config.faults.never_stable = true;
  Rig rig(config);
  ASSERT_TRUE(rig.table.Connect().has_value());
  ASSERT_TRUE(rig.table.SetRate(0.3).has_value());
  const std::int64_t start = rig.clock.NowNs();
  const auto stable = rig.table.WaitUntilStable(Criteria(5.0));
  ASSERT_FALSE(stable.has_value());
  EXPECT_EQ(stable.error().code, RateTableErrorCode::kNotStable);
  EXPECT_NEAR(static_cast<double>(rig.clock.NowNs() - start) * 1e-9, 5.0, 0.1);
  // The rate itself is there; only the table's at-rate bit never comes.
  EXPECT_NEAR(rig.table.SenseTrueRateRadS(), 0.3, 1e-6);
}

TEST(InProcessRateTableTest, ScheduledFaultLatchesAndRefusesMotionUntilReset) {
  InProcessRateTableConfig config;
  config.faults.fault_after_s = 2.0;
  Rig rig(config);
  ASSERT_TRUE(rig.table.Connect().has_value());
  ASSERT_TRUE(rig.table.SetRate(0.4).has_value());
  ASSERT_TRUE(rig.table.WaitUntilStable(Criteria()).has_value());  // ~1.3 s: before the fault
  rig.clock.SleepForNs(9 * kNsPerS / 10);  // past the fault, within the watchdog's second
  // The gyro's view fires the fault even though the owner called nothing since.
  rig.table.SenseTrueRateRadS();
  EXPECT_EQ(rig.table.counters().faults_injected, 1u);
  const auto status = rig.table.ReadStatus();
  ASSERT_TRUE(status.has_value());
  EXPECT_TRUE(status->fault);
  EXPECT_EQ(status->fault_code, static_cast<std::uint16_t>(hw::RateTableFault::kDrive));
  EXPECT_EQ(rig.table.SetRate(0.4).error().code, RateTableErrorCode::kFaulted);
  EXPECT_EQ(rig.table.WaitUntilStable(Criteria()).error().code, RateTableErrorCode::kFaulted);
  ASSERT_TRUE(rig.table.ResetFault().has_value());
  EXPECT_EQ(rig.table.state(), TableLinkState::kConnected);
  EXPECT_TRUE(rig.table.SetRate(0.1).has_value());
}

TEST(InProcessRateTableTest, InjectedTimeoutsCostTheResponseTimeAndRecover) {
  Rig rig;
  ASSERT_TRUE(rig.table.Connect().has_value());
  rig.table.FailNextCalls(2, RateTableErrorCode::kTimeout);
  const std::int64_t start = rig.clock.NowNs();
  EXPECT_EQ(rig.table.ReadStatus().error().code, RateTableErrorCode::kTimeout);
  EXPECT_EQ(rig.table.SetRate(0.1).error().code, RateTableErrorCode::kTimeout);
  // 2 calls x 2 attempts x 200 ms.
  EXPECT_EQ(rig.clock.NowNs() - start, 800'000'000);
  EXPECT_EQ(rig.table.counters().timeouts, 2u);
  EXPECT_EQ(rig.table.state(), TableLinkState::kConnected);
  EXPECT_TRUE(rig.table.SetRate(0.1).has_value());
}

TEST(InProcessRateTableTest, LostConnectionNeedsAReconnect) {
  Rig rig;
  ASSERT_TRUE(rig.table.Connect().has_value());
  rig.table.FailNextCalls(1, RateTableErrorCode::kConnectionLost);
  EXPECT_EQ(rig.table.ReadStatus().error().code, RateTableErrorCode::kConnectionLost);
  EXPECT_EQ(rig.table.state(), TableLinkState::kDisconnected);
  EXPECT_EQ(rig.table.ReadStatus().error().code, RateTableErrorCode::kNotConnected);
  EXPECT_EQ(rig.table.counters().connection_losses, 1u);
  ASSERT_TRUE(rig.table.Connect().has_value());
  EXPECT_TRUE(rig.table.ReadStatus().has_value());
}

TEST(InProcessRateTableTest, UnresponsiveTableTimesOutAndSafeStopKeepsItsBudget) {
  InProcessRateTableConfig config;
  config.faults.unresponsive_after_s = 2.0;
  Rig rig(config);
  ASSERT_TRUE(rig.table.Connect().has_value());
  ASSERT_TRUE(rig.table.SetRate(0.5).has_value());
  ASSERT_TRUE(rig.table.WaitUntilStable(Criteria()).has_value());
  rig.clock.SleepForNs(kNsPerS);
  EXPECT_EQ(rig.table.ReadStatus().error().code, RateTableErrorCode::kTimeout);
  const std::int64_t start = rig.clock.NowNs();
  rig.table.SafeStop();  // cannot reach the table
  const std::int64_t spent = rig.clock.NowNs() - start;
  EXPECT_GE(spent, 1'000'000'000);
  EXPECT_LE(spent, 1'200'000'000);  // budget + one response timeout
  // The table's watchdog is the second line of defence: it has stopped the table by now.
  EXPECT_TRUE(rig.physics_model.Status().fault);
}

TEST(InProcessRateTableTest, SafeStopCommandsZeroFromAnyState) {
  Rig rig;
  rig.table.SafeStop();  // not even connected: still commands the table (no throw)
  ASSERT_TRUE(rig.table.Connect().has_value());
  ASSERT_TRUE(rig.table.SetRate(1.0).has_value());
  rig.clock.SleepForNs(kNsPerS / 2);
  rig.table.SafeStop();
  EXPECT_EQ(rig.table.target_rate_rad_s(), 0.0);
  const hw::RateTableStatus status = rig.physics_model.Status();
  EXPECT_EQ(status.mode, hw::RateTableMode::kIdle);
  EXPECT_EQ(status.commanded_rate_rad_s, 0.0);
  static_assert(noexcept(rig.table.SafeStop()));
}

TEST(InProcessRateTableTest, ReadAngleIsThePhysicsEncoderAtTheClocksNow) {
  sim::TablePhysicsOptions physics;
  physics.encoder_noise_rad = 0.0;
  physics.noise_rad_s = 0.0;
  Rig rig({}, physics);
  EXPECT_EQ(rig.table.ReadAngle().error().code, RateTableErrorCode::kNotConnected);
  ASSERT_TRUE(rig.table.Connect().has_value());
  ASSERT_TRUE(rig.table.SetRate(0.5).has_value());
  ASSERT_TRUE(rig.table.WaitUntilStable(Criteria()).has_value());
  const auto wait_s = [&rig](int seconds) {  // with heartbeats: the watchdog is 1 s
    for (int i = 0; i < 10 * seconds; ++i) {
      rig.clock.Advance(kNsPerS / 10);
      ASSERT_TRUE(rig.table.Heartbeat().has_value());
    }
  };
  wait_s(2);  // settled to the last bit (40 time constants)
  const auto first = rig.table.ReadAngle();
  ASSERT_TRUE(first.has_value()) << first.error().ToString();
  EXPECT_TRUE(first->valid);
  EXPECT_EQ(first->t_ns, rig.clock.NowNs());
  EXPECT_EQ(first->window_ns, 0);  // sampled at the clock's now: no read-time jitter
  EXPECT_EQ(first->counts_per_rev, physics.encoder_counts_per_rev);
  wait_s(10);
  const auto second = rig.table.ReadAngle();
  ASSERT_TRUE(second.has_value());
  // 5 rad in 10 s; the two floors leave one count of doubt.
  const auto counts = static_cast<std::int32_t>(second->count - first->count);
  EXPECT_NEAR(counts * first->RadPerCount(), 5.0, first->RadPerCount());
}

TEST(InProcessRateTableTest, ReadAngleFailsAsTheOtherCallsDoAndWorksWhenFaulted) {
  Rig rig;
  ASSERT_TRUE(rig.table.Connect().has_value());
  rig.table.FailNextCalls(1, RateTableErrorCode::kTimeout);
  const std::int64_t before = rig.clock.NowNs();
  EXPECT_EQ(rig.table.ReadAngle().error().code, RateTableErrorCode::kTimeout);
  EXPECT_EQ(rig.clock.NowNs() - before, 2 * 200'000'000);  // two attempts of 200 ms each
  EXPECT_TRUE(rig.table.ReadAngle().has_value());
  rig.physics_model.InjectFault(hw::RateTableFault::kDrive);
  ASSERT_TRUE(rig.table.ReadStatus().has_value());
  EXPECT_EQ(rig.table.state(), TableLinkState::kFaulted);
  EXPECT_TRUE(rig.table.ReadAngle().has_value());
}

}  // namespace
}  // namespace hrgbench::drivers::sim_station
