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

// The stuff bits of real frames' own bit streams. Expected counts from classic_stuff_bits.py beside
// this file (an independent Python bit-level encoder of ISO 11898-1's classic frame: fields, CRC-15
// 0x4599, the stuffing rule), not from this header.
TEST(CanFrameBits, StuffBitsOfAClassicFrameAreThoseItsBitStreamNeeds) {
  const auto frame = [](std::uint32_t id, std::initializer_list<std::uint8_t> data,
                        bool extended = false) {
    CanFrame f;
    f.id = id;
    f.extended = extended;
    f.length = static_cast<std::uint8_t>(data.size());
    std::size_t i = 0;
    for (std::uint8_t b : data) f.data[i++] = b;
    return f;
  };
  EXPECT_EQ(ClassicStuffBits(frame(0x000, {0, 0, 0, 0, 0, 0, 0, 0})), 16);
  EXPECT_EQ(ClassicStuffBits(frame(0x7FF, {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF})), 15);
  // A SampleA frame of the gyro protocol (golden frame 100#2A0000400000E002).
  EXPECT_EQ(ClassicStuffBits(frame(0x100, {0x2A, 0, 0, 0x40, 0, 0, 0xE0, 0x02})), 12);
  EXPECT_EQ(ClassicStuffBits(frame(0x1ABCDEF0, {0xDE, 0xAD, 0xBE, 0xEF}, true)), 4);
  EXPECT_EQ(ClassicStuffBits(frame(0x123, {})), 1);
  // Never more than the worst case; StuffedFrameBits adds exactly them to the unstuffed count.
  const CanFrame zeros = frame(0x000, {0, 0, 0, 0, 0, 0, 0, 0});
  EXPECT_LE(StuffedFrameBits(zeros).nominal_bits, WorstCaseFrameBits(zeros).nominal_bits);
  EXPECT_EQ(StuffedFrameBits(zeros).nominal_bits, 111 + 16);
  // CAN FD: planned at its worst case.
  const CanFrame fd = Frame(64, false, true, true);
  EXPECT_EQ(StuffedFrameBits(fd).data_bits, WorstCaseFrameBits(fd).data_bits);
}

}  // namespace
}  // namespace hrgbench::hw
