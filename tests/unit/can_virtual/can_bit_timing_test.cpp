#include "can_virtual/can_bit_timing.hpp"

#include <gtest/gtest.h>

namespace hrgbench::drivers::can_virtual {
namespace {

hw::CanFrame Frame(std::uint8_t length, bool extended = false, bool fd = false, bool brs = false) {
  hw::CanFrame frame;
  frame.length = length;
  frame.extended = extended;
  frame.fd = fd;
  frame.bit_rate_switch = brs;
  return frame;
}

TEST(CanBitTiming, ClassicStandardFrameIs47BitsPlus8PerByte) {
  EXPECT_EQ(CountFrameBits(Frame(8)).nominal_bits, 111);  // ISO 11898-1 without stuff bits
  EXPECT_EQ(CountFrameBits(Frame(0)).nominal_bits, 47);
  EXPECT_EQ(FrameDurationNs(Frame(8), 1'000'000, 0), 111'000);
  EXPECT_EQ(FrameDurationNs(Frame(8), 500'000, 0), 222'000);
}

TEST(CanBitTiming, ExtendedFrameAdds20Bits) {
  EXPECT_EQ(CountFrameBits(Frame(8, true)).nominal_bits, 131);
}

TEST(CanBitTiming, RemoteFrameCarriesNoDataBits) {
  hw::CanFrame remote = Frame(8);
  remote.remote = true;
  EXPECT_EQ(CountFrameBits(remote).nominal_bits, 47);
}

TEST(CanBitTiming, FdBitRateSwitchMovesThePayloadToTheDataRate) {
  const CanFrameBits brs = CountFrameBits(Frame(64, false, true, true));
  EXPECT_EQ(brs.nominal_bits, 17 + 12);
  EXPECT_EQ(brs.data_bits, 1 + 4 + 512 + 4 + 21 + 1);
  const CanFrameBits no_brs = CountFrameBits(Frame(64, false, true, false));
  EXPECT_EQ(no_brs.data_bits, 0);
  EXPECT_EQ(no_brs.nominal_bits, brs.nominal_bits + brs.data_bits);
  // 29 bits at 1 Mbit/s + 543 bits at 8 Mbit/s (rounded up).
  EXPECT_EQ(FrameDurationNs(Frame(64, false, true, true), 1'000'000, 8'000'000), 29'000 + 67'875);
}

TEST(CanBitTiming, FdCrcIsLongerAbove16Bytes) {
  EXPECT_EQ(CountFrameBits(Frame(20, false, true, true)).data_bits -
                CountFrameBits(Frame(16, false, true, true)).data_bits,
            32 + 4);
}

}  // namespace
}  // namespace hrgbench::drivers::can_virtual
