#include "hrgbench/hw/can_frame_bits.hpp"

#include <gtest/gtest.h>

namespace hrgbench::hw {
namespace {

CanFrame Frame(std::uint8_t length, bool extended = false, bool fd = false, bool brs = false) {
  CanFrame frame;
  frame.length = length;
  frame.extended = extended;
  frame.fd = fd;
  frame.bit_rate_switch = brs;
  return frame;
}

TEST(CanFrameBits, ClassicStandardFrameIs47BitsPlus8PerByte) {
  EXPECT_EQ(CountFrameBits(Frame(8)).nominal_bits, 111);  // ISO 11898-1 without stuff bits
  EXPECT_EQ(CountFrameBits(Frame(0)).nominal_bits, 47);
  EXPECT_EQ(FrameDurationNs(Frame(8), 1'000'000, 0), 111'000);
  EXPECT_EQ(FrameDurationNs(Frame(8), 500'000, 0), 222'000);
}

TEST(CanFrameBits, ExtendedFrameAdds20Bits) {
  EXPECT_EQ(CountFrameBits(Frame(8, true)).nominal_bits, 131);
}

TEST(CanFrameBits, RemoteFrameCarriesNoDataBits) {
  CanFrame remote = Frame(8);
  remote.remote = true;
  EXPECT_EQ(CountFrameBits(remote).nominal_bits, 47);
}

TEST(CanFrameBits, FdBitRateSwitchMovesThePayloadToTheDataRate) {
  const CanFrameBits brs = CountFrameBits(Frame(64, false, true, true));
  EXPECT_EQ(brs.nominal_bits, 17 + 12);
  EXPECT_EQ(brs.data_bits, 1 + 4 + 512 + 4 + 21 + 1);
  const CanFrameBits no_brs = CountFrameBits(Frame(64, false, true, false));
  EXPECT_EQ(no_brs.data_bits, 0);
  EXPECT_EQ(no_brs.nominal_bits, brs.nominal_bits + brs.data_bits);
  // 29 bits at 1 Mbit/s + 543 bits at 8 Mbit/s (rounded up).
  EXPECT_EQ(FrameDurationNs(Frame(64, false, true, true), 1'000'000, 8'000'000), 29'000 + 67'875);
}

TEST(CanFrameBits, FdCrcIsLongerAbove16Bytes) {
  EXPECT_EQ(CountFrameBits(Frame(20, false, true, true)).data_bits -
                CountFrameBits(Frame(16, false, true, true)).data_bits,
            32 + 4);
}

// Worst-case stuffing, derived by hand from ISO 11898-1: the stuffed fields of a classic standard
// 8-byte frame are SOF..CRC = 19 + 64 + 15 = 98 bits, at most (98 - 1) / 4 = 24 stuff bits
// (drivers/gyro_can/README.md "Bus load": 135 bits).
TEST(CanFrameBits, WorstCaseStuffingOfAClassicFrame) {
  EXPECT_EQ(WorstCaseFrameBits(Frame(8)).nominal_bits, 111 + 24);
  EXPECT_EQ(FrameDurationNs(WorstCaseFrameBits(Frame(8)), 1'000'000, 0), 135'000);
  // Extended: 39 + 64 + 15 = 118 stuffed bits, 29 stuff bits.
  EXPECT_EQ(WorstCaseFrameBits(Frame(8, true)).nominal_bits, 131 + 29);
  EXPECT_EQ(WorstCaseFrameBits(Frame(0)).nominal_bits, 47 + (19 + 15 - 1) / 4);
}

// A 64-byte FD frame with BRS: arbitration 17 bits (+4 stuff) and the 12-bit trailer at the
// nominal rate; ESI + DLC + 512 data bits (+129 stuff), one fixed stuff bit before the 4-bit stuff
// count, CRC 21 (+6 fixed stuff) and its delimiter at the data rate: 34 µs + 679 bits at 5 Mbit/s,
// about 170 µs (drivers/gyro_can/README.md).
TEST(CanFrameBits, WorstCaseStuffingOfAnFdFrame) {
  const CanFrameBits worst = WorstCaseFrameBits(Frame(64, false, true, true));
  EXPECT_EQ(worst.nominal_bits, 17 + 4 + 12);
  EXPECT_EQ(worst.data_bits, 517 + 129 + 1 + 4 + 21 + 6 + 1);
  EXPECT_EQ(FrameDurationNs(worst, 1'000'000, 5'000'000), 33'000 + 135'800);
}

}  // namespace
}  // namespace hrgbench::hw
