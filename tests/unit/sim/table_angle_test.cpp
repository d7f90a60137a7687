// The simulated table's angle and encoder (TablePhysics::Angle, TrueAngleRad) on a ManualClock:
// the integral of the rate model checked against a closed form derived here, not from the code's
// own update; the encoder's quantisation, wrap and read noise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "sim/table_physics.hpp"

namespace hrgbench::drivers::sim {
namespace {

constexpr std::int64_t kMs = 1'000'000;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
using hw::RateTableMode;

TablePhysicsOptions Quiet() {
  TablePhysicsOptions o;
  o.noise_rad_s = 0.0;
  o.encoder_noise_rad = 0.0;
  o.accel_limit_rad_s2 = 1.0;
  o.settle_time_constant_s = 0.05;
  o.step_s = 1e-3;
  o.watchdog_ms = 60000;  // the tests below run for a minute without heartbeats
  return o;
}

// Advances in steps of `step_ms` up to `total_ms`, heartbeating on the way.
void RunFor(hw::ManualClock& clock, TablePhysics& table, std::int64_t total_ms,
            std::int64_t step_ms = 100) {
  for (std::int64_t t = 0; t < total_ms; t += step_ms) {
    clock.Advance(step_ms * kMs);
    table.Heartbeat(static_cast<std::uint16_t>(t / step_ms));
  }
}

TEST(TableAngle, FromRestTheAngleIsTheRampsIntegralLessTheLag) {
  // Derivation (independent of the update code). The ramp r is a staircase: the step k = 1..K
  // (dt = step_s) holds r_k = a k dt, K = omega / (a dt); its integral is
  // a dt^2 K (K + 1) / 2 = omega T_r / 2 + omega dt / 2, T_r = omega / a. The rate w follows r by
  // dw/dt = (r - w) / tau exactly within each step (r held), so the integral of (r - w) over any
  // time is tau (w_end - w_start) = tau omega once settled. Hence, long after the ramp:
  //   phi(t) = omega t - omega T_r / 2 + omega dt / 2 - omega tau.
  hw::ManualClock clock;
  const TablePhysicsOptions o = Quiet();
  TablePhysics table(o, clock);
  const double omega = 1.0;
  ASSERT_TRUE(table.Command(RateTableMode::kRate, omega));
  RunFor(clock, table, 5000);  // ramp 1 s, then 80 time constants: the lag's tail is e^-80
  const double t = 5.0, t_ramp = omega / o.accel_limit_rad_s2;
  const double expected =
      omega * t - omega * t_ramp / 2 + omega * o.step_s / 2 - omega * o.settle_time_constant_s;
  // Tolerance: 5000 steps of rounding at |phi| ~ 5 rad (1e-15 each), far below this.
  EXPECT_NEAR(table.TrueAngleRad(), expected, 1e-10);
  // Settled: the angle grows at exactly the rate over any later stretch.
  const double phi0 = table.TrueAngleRad();
  RunFor(clock, table, 10000);
  EXPECT_NEAR(table.TrueAngleRad() - phi0, omega * 10.0, 1e-10);
}

TEST(TableAngle, RateAndAngleAgreeAtEveryStep) {
  // The derivative of the angle is the rate: over a short stretch, (phi(t+h) - phi(t)) / h lies
  // between the rates at t and t + h (w is monotonic during a ramp up).
  hw::ManualClock clock;
  TablePhysics table(Quiet(), clock);
  ASSERT_TRUE(table.Command(RateTableMode::kRate, 0.8));
  for (int i = 0; i < 150; ++i) {
    const double phi0 = table.TrueAngleRad();
    const double w0 = table.TrueRateRadS();
    clock.Advance(10 * kMs);
    table.Heartbeat(static_cast<std::uint16_t>(i));
    const double mean = (table.TrueAngleRad() - phi0) / 0.01;
    const double w1 = table.TrueRateRadS();
    EXPECT_GE(mean, std::min(w0, w1) - 1e-12) << "at " << i;
    EXPECT_LE(mean, std::max(w0, w1) + 1e-12) << "at " << i;
  }
}

TEST(TableAngle, CountIsTheFloorOfTheAngleInCounts) {
  // 360 counts per revolution: one count per degree, so the expected counts are read off by hand.
  hw::ManualClock clock;
  auto o = Quiet();
  o.encoder_counts_per_rev = 360;
  o.settle_time_constant_s = 1e-4;  // settles within one 1 ms step
  o.accel_limit_rad_s2 = 50.0;
  o.max_accel_rad_s2 = 50.0;
  TablePhysics table(o, clock);
  auto a = table.Angle();
  EXPECT_TRUE(a.valid);
  EXPECT_EQ(a.counts_per_rev, 360u);
  EXPECT_EQ(a.count, 0u);  // floor(0) at power-on
  EXPECT_EQ(a.window_ns, 0);
  EXPECT_DOUBLE_EQ(a.RadPerCount(), kTwoPi / 360);
  ASSERT_TRUE(table.Command(RateTableMode::kRate, 0.5));
  RunFor(clock, table, 2000, 10);
  table.Command(RateTableMode::kIdle, 0.0);
  RunFor(clock, table, 500, 10);  // stopped again: the angle no longer moves
  const double phi = table.TrueAngleRad();
  a = table.Angle();
  EXPECT_EQ(a.count, static_cast<std::uint32_t>(std::floor(phi * 180.0 / std::numbers::pi)));
  EXPECT_EQ(a.t_ns, clock.NowNs());
  // About 1 rad turned (0.5 rad/s for 2 s, less the ramps): 57 degrees, give or take the ramps.
  EXPECT_GT(a.count, 50u);
  EXPECT_LT(a.count, 58u);
}

TEST(TableAngle, NegativeAnglesWrapModulo2To32) {
  hw::ManualClock clock;
  auto o = Quiet();
  o.encoder_counts_per_rev = 1u << 23;
  TablePhysics table(o, clock);
  ASSERT_TRUE(table.Command(RateTableMode::kRate, -0.001));
  RunFor(clock, table, 3000);
  const double phi = table.TrueAngleRad();
  ASSERT_LT(phi, 0.0);
  const double counts = std::floor(phi * (1u << 23) / kTwoPi);  // about -4000
  const auto a = table.Angle();
  EXPECT_EQ(a.count, static_cast<std::uint32_t>(4294967296.0 + counts));
  // A difference taken modulo 2^32 as a signed number is the true count difference.
  EXPECT_EQ(static_cast<std::int32_t>(a.count - 0u), static_cast<std::int64_t>(counts));
}

TEST(TableAngle, ReadNoiseHasTheStatedSpreadAndLeavesTheRateNoiseAlone) {
  // 2^30 counts/rev (q = 5.9e-9 rad): quantisation adds q^2 / 12, 3e-7 of the variance below.
  hw::ManualClock clock;
  auto o = Quiet();
  o.encoder_counts_per_rev = 1u << 30;
  o.encoder_noise_rad = 1e-5;
  o.noise_rad_s = 1e-3;
  o.seed = 11;
  TablePhysics reads_angle(o, clock);
  TablePhysics does_not(o, clock);
  std::vector<double> angles;
  for (int i = 0; i < 4000; ++i) {
    const auto a = reads_angle.Angle();
    angles.push_back(static_cast<std::int32_t>(a.count) * a.RadPerCount());
    // The rate noise sequence is the one of a table whose angle is never read.
    ASSERT_EQ(reads_angle.Status().measured_rate_rad_s, does_not.Status().measured_rate_rad_s);
  }
  double sum = 0.0, sum2 = 0.0;
  for (double x : angles) sum += x;
  const double mean = sum / static_cast<double>(angles.size());
  for (double x : angles) sum2 += (x - mean) * (x - mean);
  const double std = std::sqrt(sum2 / static_cast<double>(angles.size() - 1));
  // 4000 draws: the sample std scatters by 1/sqrt(2 * 4000) = 1.1 %; 5 % is 4.5 of that.
  EXPECT_NEAR(std, 1e-5, 0.05e-5);
  EXPECT_NEAR(mean, 0.0, 5 * 1e-5 / std::sqrt(4000.0));
}

TEST(TableAngle, EncoderOptionsAreValidated) {
  auto o = Quiet();
  std::string why;
  EXPECT_TRUE(o.IsValid(&why)) << why;
  o.encoder_counts_per_rev = 0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("encoder_counts_per_rev"), std::string::npos);
  o = Quiet();
  o.encoder_noise_rad = -1e-6;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("encoder_noise_rad"), std::string::npos);
  o.encoder_noise_rad = std::nan("");
  EXPECT_FALSE(o.IsValid(&why));
}

}  // namespace
}  // namespace hrgbench::drivers::sim
