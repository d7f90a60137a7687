// The "stable" decision: status bit AND |measured - target| <= tolerance AND no fault, for a dwell
// window, timed on a ManualClock (auto-advance: each poll's sleep moves time by the poll period).
#include "modbus_rate_table/stable_wait.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace hrgbench::drivers::modbus_rate_table {
namespace {

constexpr std::int64_t kMs = 1'000'000;

hw::RateTableStatus At(std::int64_t t_ns, double measured, bool stable_bit, bool fault = false) {
  hw::RateTableStatus s;
  s.t_ns = t_ns;
  s.measured_rate_rad_s = measured;
  s.rate_stable = stable_bit;
  s.fault = fault;
  return s;
}

TEST(StableDetector, NeedsAllConditionsForTheWholeDwell) {
  StableDetector d(/*tolerance_rad_s=*/0.01, /*dwell_ns=*/100 * kMs);
  EXPECT_FALSE(d.Update(At(0, 1.0, true), 1.0));  // window opens
  EXPECT_FALSE(d.Update(At(50 * kMs, 1.005, true), 1.0));
  EXPECT_TRUE(d.Update(At(100 * kMs, 0.995, true), 1.0));  // held 100 ms
}

TEST(StableDetector, AnyBreakRestartsTheWindow) {
  StableDetector d(0.01, 100 * kMs);
  EXPECT_FALSE(d.Update(At(0, 1.0, true), 1.0));
  EXPECT_FALSE(d.Update(At(60 * kMs, 1.02, true), 1.0));  // out of tolerance
  EXPECT_FALSE(d.Update(At(120 * kMs, 1.0, true), 1.0));  // reopens at 120
  EXPECT_FALSE(d.Update(At(200 * kMs, 1.0, true), 1.0));
  EXPECT_TRUE(d.Update(At(220 * kMs, 1.0, true), 1.0));
}

TEST(StableDetector, TableBitAloneIsNotEnoughNorIsToleranceAlone) {
  StableDetector d(0.01, 0);
  EXPECT_FALSE(d.Update(At(0, 1.5, true), 1.0));              // bit set, rate off
  EXPECT_FALSE(d.Update(At(kMs, 1.0, false), 1.0));           // rate on, bit clear
  EXPECT_FALSE(d.Update(At(2 * kMs, 1.0, true, true), 1.0));  // fault bit
  hw::RateTableStatus estop = At(3 * kMs, 1.0, true);
  estop.estop = true;
  EXPECT_FALSE(d.Update(estop, 1.0));
  EXPECT_TRUE(d.Update(At(4 * kMs, 1.0, true), 1.0));
}

// A scripted table: statuses follow the ManualClock's time.
struct ScriptedTable {
  hw::ManualClock& clock;
  std::function<hw::RateTableStatus(std::int64_t)> script;
  int reads = 0;
  std::expected<hw::RateTableStatus, hw::RateTableError> operator()() {
    ++reads;
    return script(clock.NowNs());
  }
};

TEST(WaitForStableRate, ReturnsOnceStableForDwellOnTheClock) {
  hw::ManualClock clock(0, /*auto_advance=*/true);
  // Reaches 0.5 rad/s and sets its bit at t = 1 s.
  ScriptedTable table{clock, [](std::int64_t t) {
                        const bool there = t >= 1000 * kMs;
                        return At(t, there ? 0.5 : 0.25, there);
                      }};
  const hw::StableCriteria criteria{
      .tolerance_rad_s = 1e-3, .dwell_s = 0.5, .timeout_s = 10.0, .poll_period_s = 0.1};
  const auto r = WaitForStableRate(std::ref(table), clock, 0.5, criteria);
  ASSERT_TRUE(r) << r.error().ToString();
  EXPECT_EQ(r->t_ns, 1500 * kMs);
  EXPECT_EQ(clock.NowNs(), 1500 * kMs);
}

TEST(WaitForStableRate, TimesOutWithTheLastMeasurement) {
  hw::ManualClock clock(0, true);
  ScriptedTable table{clock, [](std::int64_t t) { return At(t, 0.49, true); }};
  const hw::StableCriteria criteria{
      .tolerance_rad_s = 1e-3, .dwell_s = 0.5, .timeout_s = 2.0, .poll_period_s = 0.1};
  const auto r = WaitForStableRate(std::ref(table), clock, 0.5, criteria);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, hw::RateTableErrorCode::kNotStable);
  EXPECT_NE(r.error().message.find("0.49"), std::string::npos) << r.error().message;
  EXPECT_EQ(clock.NowNs(), 2000 * kMs);
  EXPECT_EQ(table.reads, 21);
}

TEST(WaitForStableRate, FaultEndsTheWaitAtOnce) {
  hw::ManualClock clock(0, true);
  ScriptedTable table{clock, [](std::int64_t t) {
                        auto s = At(t, 0.5, true, t >= 300 * kMs);
                        s.fault_code = s.fault ? 1 : 0;
                        return s;
                      }};
  const hw::StableCriteria criteria{
      .tolerance_rad_s = 1e-3, .dwell_s = 1.0, .timeout_s = 10.0, .poll_period_s = 0.1};
  const auto r = WaitForStableRate(std::ref(table), clock, 0.5, criteria);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, hw::RateTableErrorCode::kFaulted);
  EXPECT_NE(r.error().message.find("watchdog"), std::string::npos) << r.error().message;
  EXPECT_EQ(clock.NowNs(), 300 * kMs);
}

TEST(WaitForStableRate, TransportErrorIsPassedThroughAndBadCriteriaRejected) {
  hw::ManualClock clock(0, true);
  StatusReader failing = [] {
    return std::expected<hw::RateTableStatus, hw::RateTableError>(
        std::unexpected(hw::RateTableError{hw::RateTableErrorCode::kTimeout, "no reply"}));
  };
  auto r = WaitForStableRate(failing, clock, 0.0, {});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, hw::RateTableErrorCode::kTimeout);
  r = WaitForStableRate(failing, clock, 0.0, {.dwell_s = 5.0, .timeout_s = 1.0});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, hw::RateTableErrorCode::kInvalidConfig);
}

}  // namespace
}  // namespace hrgbench::drivers::modbus_rate_table
