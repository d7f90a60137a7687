// The wire format: float32 high word first, status bits at their documented positions.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>

#include "modbus_rate_table/register_map.hpp"

namespace hrgbench::drivers::modbus_rate_table {
namespace {

TEST(RegisterCodec, Float32IsHighWordFirst) {
  // IEEE-754 bit patterns worked out by hand: 1.0f = 0x3F800000, -2.5f = 0xC0200000,
  // 0.1f = 0x3DCCCCCD (rounded up).
  EXPECT_EQ(EncodeFloat32(1.0f), (std::array<std::uint16_t, 2>{0x3F80, 0x0000}));
  EXPECT_EQ(EncodeFloat32(-2.5f), (std::array<std::uint16_t, 2>{0xC020, 0x0000}));
  EXPECT_EQ(EncodeFloat32(0.1f), (std::array<std::uint16_t, 2>{0x3DCC, 0xCCCD}));
  EXPECT_EQ(DecodeFloat32(0x3F80, 0x0000), 1.0f);
  EXPECT_EQ(DecodeFloat32(0x3DCC, 0xCCCD), 0.1f);
  // Swapped words are a different number: the order matters and is not symmetric.
  EXPECT_NE(DecodeFloat32(0xCCCD, 0x3DCC), 0.1f);
}

TEST(RegisterCodec, Float32RoundTripsSpecialValues) {
  for (float v : {0.0f, -0.0f, 7.292115e-5f, -1.0f, 1e-30f, 3.4e38f,
                  std::numeric_limits<float>::infinity()}) {
    const auto w = EncodeFloat32(v);
    EXPECT_EQ(std::bit_cast<std::uint32_t>(DecodeFloat32(w[0], w[1])),
              std::bit_cast<std::uint32_t>(v));
  }
  const auto nan = EncodeFloat32(std::numeric_limits<float>::quiet_NaN());
  EXPECT_TRUE(std::isnan(DecodeFloat32(nan[0], nan[1])));
}

TEST(RegisterCodec, StatusBitsAtDocumentedPositions) {
  hw::RateTableStatus s;
  s.rate_stable = true;
  EXPECT_EQ(PackStatusBits(s), 0x0001);
  s = {};
  s.in_motion = true;
  EXPECT_EQ(PackStatusBits(s), 0x0002);
  s = {};
  s.fault = true;
  EXPECT_EQ(PackStatusBits(s), 0x0004);
  s = {};
  s.estop = true;
  EXPECT_EQ(PackStatusBits(s), 0x0008);
  s = {};
  s.interlock_open = true;
  EXPECT_EQ(PackStatusBits(s), 0x0010);
}

TEST(RegisterCodec, StatusBlockLayoutAndRoundTrip) {
  hw::RateTableStatus s;
  s.commanded_rate_rad_s = 1.0;
  s.measured_rate_rad_s = -2.5;
  s.mode = hw::RateTableMode::kRate;
  s.in_motion = true;
  s.fault = true;
  s.fault_code = static_cast<std::uint16_t>(hw::RateTableFault::kWatchdog);
  s.heartbeat_echo = 0xBEEF;
  s.temperature_c = 0.1;
  const auto regs = EncodeStatusBlock(s);
  EXPECT_EQ(regs[0], 0x0006);  // in motion | fault
  EXPECT_EQ(regs[1], 1);       // watchdog
  EXPECT_EQ(regs[2], 0x3F80);  // commanded 1.0, high word
  EXPECT_EQ(regs[3], 0x0000);
  EXPECT_EQ(regs[4], 0xC020);  // measured -2.5, high word
  EXPECT_EQ(regs[5], 0x0000);
  EXPECT_EQ(regs[6], 1);  // rate mode
  EXPECT_EQ(regs[7], 0xBEEF);
  EXPECT_EQ(regs[8], 0x3DCC);  // 0.1 °C
  EXPECT_EQ(regs[9], 0xCCCD);
  EXPECT_EQ(regs[10], kMapVersion);

  const auto back = DecodeStatusBlock(regs);
  EXPECT_EQ(back.commanded_rate_rad_s, 1.0);
  EXPECT_EQ(back.measured_rate_rad_s, -2.5);
  EXPECT_EQ(back.mode, hw::RateTableMode::kRate);
  EXPECT_TRUE(back.in_motion);
  EXPECT_TRUE(back.fault);
  EXPECT_FALSE(back.rate_stable);
  EXPECT_FALSE(back.estop);
  EXPECT_EQ(back.fault_code, 1);
  EXPECT_EQ(back.heartbeat_echo, 0xBEEF);
  EXPECT_FLOAT_EQ(static_cast<float>(back.temperature_c), 0.1f);
}

}  // namespace
}  // namespace hrgbench::drivers::modbus_rate_table
