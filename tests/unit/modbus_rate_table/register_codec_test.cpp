// The wire format: float32 and uint32 high word first, status bits at their documented positions,
// the status block (input 0..10) and the angle block (input 11..15) register by register.
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
  EXPECT_EQ(regs[10], 2);                     // the map with the angle block
  EXPECT_EQ(EncodeStatusBlock(s, 1)[10], 1);  // a simulator may serve the first map

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

TEST(RegisterCodec, Uint32IsHighWordFirst) {
  EXPECT_EQ(EncodeUint32(0x12345678u), (std::array<std::uint16_t, 2>{0x1234, 0x5678}));
  EXPECT_EQ(EncodeUint32(8388608u), (std::array<std::uint16_t, 2>{0x0080, 0x0000}));  // 2^23
  EXPECT_EQ(EncodeUint32(0xFFFFFFFFu), (std::array<std::uint16_t, 2>{0xFFFF, 0xFFFF}));
  EXPECT_EQ(DecodeUint32(0x1234, 0x5678), 0x12345678u);
  EXPECT_EQ(DecodeUint32(0x5678, 0x1234), 0x56781234u);  // swapped words: another number
}

TEST(RegisterCodec, AngleBlockAddressesAreTheDocumentedOnes) {
  // README.md: 11 encoder status, 12-13 count, 14-15 counts per revolution; 16 registers in all,
  // the status block's 11 unchanged from version 1.
  EXPECT_EQ(input::kStatusCount, 11);
  EXPECT_EQ(input::kEncoderStatus, 11);
  EXPECT_EQ(input::kEncoderCount, 12);
  EXPECT_EQ(input::kCountsPerRev, 14);
  EXPECT_EQ(input::kAngleFirst + input::kAngleCount, input::kCount);
  EXPECT_EQ(input::kCount, 16);
  EXPECT_EQ(kMapVersion, 2);
  EXPECT_EQ(kOldestMapVersion, 1);
  EXPECT_EQ(encoder_bit::kPositionValid, 0x0001);
}

TEST(RegisterCodec, AngleBlockLayoutAndRoundTrip) {
  hw::RateTableAngle a;
  a.valid = true;
  a.count = 0xFEDCBA98u;
  a.counts_per_rev = 1u << 23;
  a.t_ns = 123;  // not on the wire
  a.window_ns = 456;
  const auto regs = EncodeAngleBlock(a);
  ASSERT_EQ(regs.size(), 5u);
  EXPECT_EQ(regs[0], 0x0001);  // input 11: position valid
  EXPECT_EQ(regs[1], 0xFEDC);  // input 12: count, high word
  EXPECT_EQ(regs[2], 0xBA98);  // input 13
  EXPECT_EQ(regs[3], 0x0080);  // input 14: 2^23 counts/rev, high word
  EXPECT_EQ(regs[4], 0x0000);  // input 15
  const auto back = DecodeAngleBlock(regs);
  EXPECT_TRUE(back.valid);
  EXPECT_EQ(back.count, 0xFEDCBA98u);
  EXPECT_EQ(back.counts_per_rev, 1u << 23);
  EXPECT_EQ(back.t_ns, 0);
  EXPECT_EQ(back.window_ns, 0);
  a.valid = false;
  EXPECT_EQ(EncodeAngleBlock(a)[0], 0x0000);
  // Other bits of the encoder status word are reserved: only bit 0 says valid.
  const std::array<std::uint16_t, 5> reserved_bits{0xFFFE, 0, 1, 0, 360};
  EXPECT_FALSE(DecodeAngleBlock(reserved_bits).valid);
}

}  // namespace
}  // namespace hrgbench::drivers::modbus_rate_table
