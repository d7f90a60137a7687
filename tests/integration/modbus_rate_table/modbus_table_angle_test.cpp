// The encoder angle over Modbus TCP on 127.0.0.1 (register map version 2, input 11..15): read raw
// with libmodbus and decoded by hand here (not with the codec under test), then through the
// driver's ReadAngle; a table of map version 1 (no angle) and what the driver makes of it.
//
// Both the simulator's physics and the driver run on SteadyClock (CLOCK_MONOTONIC), one time
// base, so an angle's time stamp can be checked against the table's true rate. No assertion
// depends on how fast this machine is: the bounds are built from the read windows measured.
#include <gtest/gtest.h>
#include <modbus.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <numbers>
#include <thread>
#include <vector>

#include "modbus_rate_table/modbus_rate_table.hpp"
#include "modbus_rate_table/register_map.hpp"
#include "sim_table_fixture.hpp"

namespace hrgbench::drivers::modbus_rate_table {
namespace {

using hw::RateTableErrorCode;
using testing::FastTable;
using testing::SimTable;

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// FC 04 with libmodbus; empty when refused (*error_number gets errno).
std::vector<std::uint16_t> RawReadInput(int port, int address, int count,
                                        int* error_number = nullptr) {
  modbus_t* ctx = modbus_new_tcp("127.0.0.1", port);
  std::vector<std::uint16_t> regs(static_cast<std::size_t>(count));
  if (ctx == nullptr || modbus_connect(ctx) == -1) {
    if (ctx != nullptr) modbus_free(ctx);
    regs.clear();
    return regs;
  }
  errno = 0;
  const int rc = modbus_read_input_registers(ctx, address, count, regs.data());
  if (error_number != nullptr) *error_number = rc == count ? 0 : errno;
  if (rc != count) regs.clear();
  modbus_close(ctx);
  modbus_free(ctx);
  return regs;
}

void Sleep(double seconds) { std::this_thread::sleep_for(std::chrono::duration<double>(seconds)); }

drivers::sim::TablePhysicsOptions ExactEncoder(std::uint32_t counts_per_rev) {
  auto o = FastTable();
  o.encoder_counts_per_rev = counts_per_rev;
  o.encoder_noise_rad = 0.0;
  return o;
}

TEST(ModbusTableAngle, RawRegistersHoldTheEncoderCountHighWordFirst) {
  SimTable sim(ExactEncoder(1u << 23));
  ASSERT_EQ(sim.Start(), "");
  // Turn the table a little and stop it, so the angle is neither 0 nor moving while it is read.
  ASSERT_TRUE(sim.physics().SetAccelLimit(50.0));
  ASSERT_TRUE(sim.physics().Command(hw::RateTableMode::kRate, 2.0));
  Sleep(0.2);
  ASSERT_TRUE(sim.physics().Command(hw::RateTableMode::kIdle, 0.0));
  Sleep(0.3);  // the ramp down takes 40 ms; the lag's tail (tau 20 ms) creeps on a little
  const double phi_before = sim.physics().TrueAngleRad();
  ASSERT_GT(phi_before, 0.1);
  const auto regs = RawReadInput(sim.port(), 0, 16);
  const double phi_after = sim.physics().TrueAngleRad();
  ASSERT_EQ(regs.size(), 16u);
  EXPECT_EQ(regs[10], 2);      // map version
  EXPECT_EQ(regs[11] & 1, 1);  // position valid
  const std::uint32_t count = (std::uint32_t{regs[12]} << 16) | regs[13];
  const std::uint32_t resolution = (std::uint32_t{regs[14]} << 16) | regs[15];
  EXPECT_EQ(resolution, 8388608u);
  // The table sampled its encoder between the two true angles: the count is floor(phi / q) of
  // an angle between them (they differ by at most the tail's 2 rad/s e^-13 tau, 1e-7 rad).
  EXPECT_GE(count, static_cast<std::uint32_t>(std::floor(phi_before * 8388608.0 / kTwoPi)));
  EXPECT_LE(count, static_cast<std::uint32_t>(std::floor(phi_after * 8388608.0 / kTwoPi)));
  EXPECT_LT(phi_after - phi_before, 1e-6);
}

TEST(ModbusTableAngle, ReadsPastTheMapAreIllegalAddress) {
  SimTable sim;
  ASSERT_EQ(sim.Start(), "");
  int error_number = 0;
  EXPECT_TRUE(RawReadInput(sim.port(), 0, 17, &error_number).empty());
  EXPECT_EQ(error_number, EMBXILADD);
  EXPECT_EQ(RawReadInput(sim.port(), 11, 5).size(), 5u);  // the angle block alone
  EXPECT_EQ(RawReadInput(sim.port(), 12, 2).size(), 2u);  // the count alone
}

TEST(ModbusTableAngle, AVersion1TableHasNoAngleRegisters) {
  drivers::sim::TableServerOptions server;
  server.map_version = 1;
  SimTable sim(FastTable(), server);
  ASSERT_EQ(sim.Start(), "");
  const auto status = RawReadInput(sim.port(), 0, 11);
  ASSERT_EQ(status.size(), 11u);
  EXPECT_EQ(status[10], 1);
  int error_number = 0;
  EXPECT_TRUE(RawReadInput(sim.port(), 11, 5, &error_number).empty());
  EXPECT_EQ(error_number, EMBXILADD);
}

TEST(ModbusTableAngle, DriverReadsTheAngleAndItsTimeAgreesWithTheRate) {
  auto physics = FastTable();  // encoder 2^23 counts/rev, read noise 1e-6 rad
  SimTable sim(physics);
  ASSERT_EQ(sim.Start(), "");
  hw::SteadyClock clock;
  ModbusRateTable table(sim.DriverConfig(), clock);
  ASSERT_TRUE(table.Connect());
  EXPECT_EQ(table.map_version(), 2);
  const double omega = 0.5;
  ASSERT_TRUE(table.SetRate(omega));
  ASSERT_TRUE(table.WaitUntilStable(
      {.tolerance_rad_s = 2e-3, .dwell_s = 0.2, .timeout_s = 10.0, .poll_period_s = 0.02}));
  Sleep(0.6);  // 30 time constants after the ramp: the lag's remainder is below 1e-13 rad/s
  ASSERT_NEAR(sim.physics().TrueRateRadS(), omega, 1e-9);  // settled: the true rate is omega

  const std::int64_t before = clock.NowNs();
  const auto first = table.ReadAngle();
  const std::int64_t after = clock.NowNs();
  ASSERT_TRUE(first) << first.error().ToString();
  EXPECT_TRUE(first->valid);
  EXPECT_EQ(first->counts_per_rev, 1u << 23);
  EXPECT_GE(first->window_ns, 0);
  EXPECT_GE(first->t_ns - first->window_ns / 2, before);  // the window lies inside the call
  EXPECT_LE(first->t_ns + first->window_ns / 2, after);
  Sleep(0.3);
  const auto second = table.ReadAngle();
  ASSERT_TRUE(second) << second.error().ToString();
  // Ω between two readings. The sampling instants lie within ± window / 2 of the stamps, so the
  // time between them is off by at most (w1 + w2) / 2: |Ω| (w1 + w2) / 2 of angle; the angle is
  // off by at most one count each (floor) plus the read noise (6 sigma each, 1e-6 rad).
  const double dt = static_cast<double>(second->t_ns - first->t_ns) * 1e-9;
  const auto counts = static_cast<std::int32_t>(second->count - first->count);
  const double omega_read = counts * first->RadPerCount() / dt;
  const double bound =
      (omega * static_cast<double>(first->window_ns + second->window_ns) * 1e-9 / 2 +
       2 * first->RadPerCount() + 2 * 6 * physics.encoder_noise_rad) /
      dt;
  EXPECT_NEAR(omega_read, omega, bound)
      << "dt " << dt << " s, windows " << first->window_ns << " and " << second->window_ns << " ns";
  const auto c = table.counters();
  EXPECT_EQ(c.timeouts + c.bad_replies + c.exception_replies, 0u);
}

TEST(ModbusTableAngle, AFaultedTableStillReportsItsAngle) {
  SimTable sim;
  ASSERT_EQ(sim.Start(), "");
  hw::SteadyClock clock;
  ModbusRateTable table(sim.DriverConfig(), clock);
  ASSERT_TRUE(table.Connect());
  sim.physics().SetEStop(true);
  ASSERT_TRUE(table.ReadStatus());
  EXPECT_EQ(table.state(), TableLinkState::kFaulted);
  const auto angle = table.ReadAngle();
  ASSERT_TRUE(angle) << angle.error().ToString();
  EXPECT_TRUE(angle->valid);
}

TEST(ModbusTableAngle, DriverOnAVersion1TableSaysNotSupportedWithoutAsking) {
  drivers::sim::TableServerOptions server;
  server.map_version = 1;
  SimTable sim(FastTable(), server);
  ASSERT_EQ(sim.Start(), "");
  hw::SteadyClock clock;
  ModbusRateTable table(sim.DriverConfig(), clock);
  ASSERT_TRUE(table.Connect()) << "a version 1 table is still a table of this driver";
  EXPECT_EQ(table.map_version(), 1);
  const auto requests = sim.server().counters().requests;
  const auto angle = table.ReadAngle();
  ASSERT_FALSE(angle);
  EXPECT_EQ(angle.error().code, RateTableErrorCode::kNotSupported);
  EXPECT_NE(angle.error().message.find("version 1"), std::string::npos) << angle.error().message;
  EXPECT_EQ(sim.server().counters().requests, requests);  // nothing was sent
  ASSERT_TRUE(table.SetRate(0.2));
  EXPECT_TRUE(table.ReadStatus());
  EXPECT_TRUE(table.Stop());
}

}  // namespace
}  // namespace hrgbench::drivers::modbus_rate_table
