// The simulated table's physics on a ManualClock: ramp at the acceleration limit, first-order
// settling, its own stable bit, watchdog, e-stop, interlock, seeded noise.
#include "sim/table_physics.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace hrgbench::drivers::sim {
namespace {

constexpr std::int64_t kMs = 1'000'000;
using hw::RateTableFault;
using hw::RateTableMode;

TablePhysicsOptions Quiet() {
  TablePhysicsOptions o;
  o.noise_rad_s = 0.0;
  o.accel_limit_rad_s2 = 1.0;
  o.settle_time_constant_s = 0.05;
  o.watchdog_ms = 1000;
  return o;
}

TEST(TablePhysics, RampsAtTheAccelerationLimitThenSettles) {
  hw::ManualClock clock;
  TablePhysics table(Quiet(), clock);
  ASSERT_TRUE(table.Command(RateTableMode::kRate, 2.0));
  // Ramp to 2 rad/s at 1 rad/s^2 takes 2 s; the lag trails by accel * tau = 0.05 rad/s.
  clock.Advance(1000 * kMs);
  table.Heartbeat(1);
  EXPECT_NEAR(table.TrueRateRadS(), 1.0 - 0.05, 2e-3);
  auto s = table.Status();
  EXPECT_TRUE(s.in_motion);
  EXPECT_FALSE(s.rate_stable);
  EXPECT_EQ(s.commanded_rate_rad_s, 2.0);
  clock.Advance(900 * kMs);
  table.Heartbeat(2);
  clock.Advance(600 * kMs);  // t = 2.5 s: ramp done 0.5 s ago, 10 time constants
  table.Heartbeat(3);
  EXPECT_NEAR(table.TrueRateRadS(), 2.0, 1e-4);
  s = table.Status();
  EXPECT_TRUE(s.rate_stable);  // within 1e-3 for more than stable_hold_s
  EXPECT_FALSE(s.fault);
  EXPECT_EQ(s.heartbeat_echo, 3);
}

TEST(TablePhysics, AccelerationNeverExceedsTheLimit) {
  hw::ManualClock clock;
  auto o = Quiet();
  o.accel_limit_rad_s2 = 0.5;
  TablePhysics table(o, clock);
  ASSERT_TRUE(table.Command(RateTableMode::kRate, 1.0));
  double previous = 0.0;
  for (int i = 0; i < 300; ++i) {
    clock.Advance(10 * kMs);
    if (i % 20 == 0) table.Heartbeat(static_cast<std::uint16_t>(i));
    const double now = table.TrueRateRadS();
    EXPECT_LE((now - previous) / 0.01, 0.5 + 1e-9) << "at step " << i;
    previous = now;
  }
}

TEST(TablePhysics, WatchdogStopsTheTableWhenHeartbeatsStop) {
  hw::ManualClock clock;
  TablePhysics table(Quiet(), clock);
  ASSERT_TRUE(table.Command(RateTableMode::kRate, 0.5));
  for (int i = 0; i < 5; ++i) {
    clock.Advance(500 * kMs);
    table.Heartbeat(static_cast<std::uint16_t>(i));
  }
  EXPECT_FALSE(table.Status().fault);
  clock.Advance(1001 * kMs);  // no heartbeat for longer than 1000 ms
  auto s = table.Status();
  EXPECT_TRUE(s.fault);
  EXPECT_EQ(s.fault_code, static_cast<std::uint16_t>(RateTableFault::kWatchdog));
  EXPECT_EQ(s.mode, RateTableMode::kIdle);
  clock.Advance(2000 * kMs);
  EXPECT_NEAR(table.TrueRateRadS(), 0.0, 1e-6);  // 0.5 rad/s at 1 rad/s^2: stopped in 0.5 s
  // Latched: a new command is refused until reset.
  EXPECT_FALSE(table.Command(RateTableMode::kRate, 0.5));
  table.ResetFault();
  EXPECT_FALSE(table.Status().fault);
  EXPECT_TRUE(table.Command(RateTableMode::kRate, 0.5));
}

TEST(TablePhysics, IdleTableNeedsNoHeartbeat) {
  hw::ManualClock clock;
  TablePhysics table(Quiet(), clock);
  clock.Advance(10'000 * kMs);
  EXPECT_FALSE(table.Status().fault);
}

TEST(TablePhysics, EStopFaultsBrakesAndSurvivesResetWhilePressed) {
  hw::ManualClock clock;
  TablePhysics table(Quiet(), clock);
  ASSERT_TRUE(table.Command(RateTableMode::kRate, 1.0));
  clock.Advance(800 * kMs);
  table.Heartbeat(1);
  table.SetEStop(true);
  clock.Advance(500 * kMs);  // 20 rad/s^2 braking: ramp at 0 in 0.04 s, then ~9 tau of lag
  auto s = table.Status();
  EXPECT_TRUE(s.estop);
  EXPECT_TRUE(s.fault);
  EXPECT_EQ(s.fault_code, static_cast<std::uint16_t>(RateTableFault::kEStop));
  EXPECT_NEAR(table.TrueRateRadS(), 0.0, 1e-3);
  table.ResetFault();
  EXPECT_TRUE(table.Status().fault);  // still pressed
  table.SetEStop(false);
  table.ResetFault();
  EXPECT_FALSE(table.Status().fault);
}

TEST(TablePhysics, ActiveModeAndLatchedFaultFollowAWatchdogTripWithoutDrawingNoise) {
  hw::ManualClock clock;
  auto o = Quiet();
  o.noise_rad_s = 1e-3;
  TablePhysics asked(o, clock);
  TablePhysics not_asked(o, clock);
  ASSERT_TRUE(asked.Command(RateTableMode::kRate, 0.2));
  ASSERT_TRUE(not_asked.Command(RateTableMode::kRate, 0.2));
  EXPECT_EQ(asked.ActiveMode(), RateTableMode::kRate);
  EXPECT_EQ(asked.LatchedFaultCode(), 0);
  clock.Advance(1500 * kMs);  // no heartbeat: the 1 s watchdog trips on its own time
  EXPECT_EQ(asked.ActiveMode(), RateTableMode::kIdle);
  EXPECT_EQ(asked.LatchedFaultCode(), static_cast<std::uint16_t>(RateTableFault::kWatchdog));
  // The queries draw no noise: the status sequence is the one of a table never asked.
  EXPECT_EQ(asked.Status().measured_rate_rad_s, not_asked.Status().measured_rate_rad_s);
  asked.ResetFault();
  EXPECT_EQ(asked.LatchedFaultCode(), 0);
  EXPECT_EQ(asked.ActiveMode(), RateTableMode::kIdle);  // a reset does not restart motion
}

TEST(TablePhysics, InterlockRefusesMotion) {
  hw::ManualClock clock;
  TablePhysics table(Quiet(), clock);
  table.SetInterlockOpen(true);
  EXPECT_FALSE(table.Command(RateTableMode::kRate, 0.1));
  const auto s = table.Status();
  EXPECT_TRUE(s.interlock_open);
  EXPECT_EQ(s.fault_code, static_cast<std::uint16_t>(RateTableFault::kInterlock));
}

TEST(TablePhysics, RefusesRatesBeyondItsHardwareLimit) {
  hw::ManualClock clock;
  auto o = Quiet();
  o.max_rate_rad_s = 3.0;
  TablePhysics table(o, clock);
  EXPECT_FALSE(table.Command(RateTableMode::kRate, 3.5));
  EXPECT_FALSE(table.Command(RateTableMode::kRate, std::nan("")));
  EXPECT_FALSE(table.SetAccelLimit(0.0));
  EXPECT_FALSE(table.SetWatchdogMs(50));
}

TEST(TablePhysics, NoiseIsSeededAndHasTheStatedSpread) {
  const auto draw = [](std::uint64_t seed) {
    hw::ManualClock clock;
    auto o = Quiet();
    o.noise_rad_s = 1e-3;
    o.seed = seed;
    TablePhysics table(o, clock);
    std::vector<double> v;
    for (int i = 0; i < 2000; ++i) v.push_back(table.Status().measured_rate_rad_s);
    return v;
  };
  const auto a = draw(7), b = draw(7), c = draw(8);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  double sum2 = 0.0;
  for (double x : a) sum2 += x * x;
  EXPECT_NEAR(std::sqrt(sum2 / static_cast<double>(a.size())), 1e-3, 1e-4);  // 2000 draws: ~2%
}

}  // namespace
}  // namespace hrgbench::drivers::sim
