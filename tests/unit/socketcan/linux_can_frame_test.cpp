// hw::CanFrame ↔ struct canfd_frame, including the flag bits the kernel packs into can_id.

#include "socketcan/linux_can_frame.hpp"

#include <gtest/gtest.h>

#include "can_frame_assertions.hpp"

namespace hrgbench::drivers::socketcan {
namespace {

hw::CanFrame RoundTrip(const hw::CanFrame& frame) {
  canfd_frame wire;
  const std::size_t bytes = ToLinuxFrame(frame, &wire);
  hw::CanFrame back;
  EXPECT_TRUE(FromLinuxFrame(wire, bytes, &back));
  return back;
}

TEST(LinuxCanFrame, ClassicExtendedRemoteAndFdSurviveTheRoundTrip) {
  hw::CanFrame classic;
  classic.id = 0x123;
  classic.length = 4;
  classic.data = {0xDE, 0xAD, 0xBE, 0xEF};
  EXPECT_TRUE(testing::SameFrame(classic, RoundTrip(classic)));

  hw::CanFrame extended = classic;
  extended.id = 0x1FFFFFFF;
  extended.extended = true;
  EXPECT_TRUE(testing::SameFrame(extended, RoundTrip(extended)));

  hw::CanFrame remote;
  remote.id = 0x7FF;
  remote.remote = true;
  remote.length = 8;
  EXPECT_TRUE(testing::SameFrame(remote, RoundTrip(remote)));

  hw::CanFrame fd;
  fd.id = 0x10;
  fd.fd = true;
  fd.bit_rate_switch = true;
  fd.length = 64;
  for (std::uint8_t i = 0; i < 64; ++i) fd.data[i] = i;
  EXPECT_TRUE(testing::SameFrame(fd, RoundTrip(fd)));
}

TEST(LinuxCanFrame, WireLayoutCarriesFlagsInCanId) {
  hw::CanFrame frame;
  frame.id = 0x12345;
  frame.extended = true;
  frame.length = 1;
  canfd_frame wire;
  EXPECT_EQ(ToLinuxFrame(frame, &wire), kClassicMtu);
  EXPECT_EQ(wire.can_id, 0x12345u | CAN_EFF_FLAG);
  frame.fd = true;
  frame.bit_rate_switch = true;
  EXPECT_EQ(ToLinuxFrame(frame, &wire), kFdMtu);
  EXPECT_EQ(wire.flags, CANFD_BRS);
}

TEST(LinuxCanFrame, ErrorFramesAndMalformedDatagramsAreRecognised) {
  canfd_frame wire{};
  wire.can_id = CAN_ERR_FLAG | 0x40;  // CAN_ERR_BUSOFF
  wire.len = 8;
  hw::CanFrame frame;
  ASSERT_TRUE(FromLinuxFrame(wire, kClassicMtu, &frame));
  EXPECT_TRUE(frame.error);
  EXPECT_EQ(frame.id, 0x40u);
  EXPECT_FALSE(FromLinuxFrame(wire, 10, &frame));  // neither CAN_MTU nor CANFD_MTU
  wire.can_id = 0x1;
  wire.len = 9;
  EXPECT_FALSE(FromLinuxFrame(wire, kClassicMtu, &frame));
}

}  // namespace
}  // namespace hrgbench::drivers::socketcan
