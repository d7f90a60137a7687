// The can-utils frame notation of the hardware layer (hrgbench/hw/can_frame_text.hpp), the one
// formatter and parser of CAN frames as text: every kind of frame written as candump writes it, the
// notation round-tripped, parsed fields, refused text and buffer bounds. The candump log line
// around the frame is tested in tests/unit/session_recorder/candump_log_test.cpp.

#include "hrgbench/hw/can_frame_text.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <initializer_list>
#include <string>

namespace hrgbench::hw {
namespace {

TEST(CanFrameTextTest, RoundTripsTheNotation) {
  for (const char* text : {"123#DEADBEEF", "123#", "7FF#0011223344556677", "1ABCDEF0#00", "123#R",
                           "123#R4", "123##1DEADBEEF", "123##0",
                           "000##1"
                           "000102030405060708090A0B0C0D0E0F101112131415161718191A1B1C1D1E1F"
                           "202122232425262728292A2B2C2D2E2F303132333435363738393A3B3C3D3E3F"}) {
    const std::optional<CanFrame> frame = ParseCanFrame(text);
    ASSERT_TRUE(frame.has_value()) << text;
    EXPECT_EQ(CanFrameToString(*frame), text);
  }
}

CanFrame Frame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) {
  CanFrame frame;
  frame.id = id;
  for (std::uint8_t b : bytes) frame.data[frame.length++] = b;
  return frame;
}

// Each kind of frame as can-utils lib.c sprint_canframe() (and so candump -L) writes it.
TEST(CanFrameTextTest, FormatsEachKindAsCandumpDoes) {
  CanFrame ext = Frame(0x1ABCDEF0, {0x00});
  ext.extended = true;
  EXPECT_EQ(CanFrameToString(ext), "1ABCDEF0#00");
  EXPECT_EQ(CanFrameToString(Frame(0x7FF, {})), "7FF#");
  CanFrame rtr = Frame(0x123, {});
  rtr.remote = true;
  EXPECT_EQ(CanFrameToString(rtr), "123#R");
  rtr.length = 4;
  EXPECT_EQ(CanFrameToString(rtr), "123#R4");
  CanFrame fd = Frame(0x123, {0xDE, 0xAD, 0xBE, 0xEF});
  fd.fd = true;
  fd.bit_rate_switch = true;
  EXPECT_EQ(CanFrameToString(fd), "123##1DEADBEEF");
  fd.bit_rate_switch = false;
  EXPECT_EQ(CanFrameToString(fd), "123##0DEADBEEF");
  // Error frame: CAN_ERR_FLAG | CAN_ERR_BUSOFF (0x40) as candump prints it, 8 data bytes. Written
  // only: the parser refuses an id with CAN_ERR_FLAG (see RejectsMalformedText).
  CanFrame error = Frame(0x40, {0, 0, 0, 0, 0, 0, 0, 0});
  error.error = true;
  EXPECT_EQ(CanFrameToString(error), "20000040#0000000000000000");
  EXPECT_FALSE(ParseCanFrame(CanFrameToString(error)).has_value());
}

// Fields a CanFrame can hold but a frame on the wire cannot: written as candump would see them.
TEST(CanFrameTextTest, FormatsImpossibleFieldsAsTheWireWouldHaveThem) {
  CanFrame wide = Frame(0xFFFFF123u, {0x01});
  EXPECT_EQ(CanFrameToString(wide), "123#01");  // 11 bits
  wide.extended = true;
  EXPECT_EQ(CanFrameToString(wide), "1FFFF123#01");  // 29 bits
  CanFrame classic = Frame(0x123, {1, 2, 3, 4, 5, 6, 7, 8, 9});
  EXPECT_EQ(CanFrameToString(classic), "123#0102030405060708");  // at most 8 classic bytes
  CanFrame remote_fd = Frame(0x123, {0xAB});
  remote_fd.fd = true;
  remote_fd.remote = true;
  EXPECT_EQ(CanFrameToString(remote_fd), "123##0AB");  // CAN FD has no remote frames
  CanFrame error_fd = Frame(0x4, {0x01});
  error_fd.error = error_fd.fd = error_fd.remote = true;
  EXPECT_EQ(CanFrameToString(error_fd), "20000004#01");  // error frames are classic data
}

TEST(CanFrameTextTest, LongestTextFitsTheBound) {
  CanFrame fd;
  fd.id = CanFrame::kExtendedIdMask;
  fd.extended = fd.fd = fd.bit_rate_switch = true;
  fd.length = CanFrame::kMaxFdLength;
  char buffer[kMaxCanFrameTextLength];
  EXPECT_EQ(FormatCanFrame(fd, buffer), kMaxCanFrameTextLength - 1);
}

TEST(CanFrameTextTest, ParsesFields) {
  const auto fd = ParseCanFrame("12345678##1de.ad.be.ef");
  ASSERT_TRUE(fd.has_value());
  EXPECT_TRUE(fd->extended);
  EXPECT_TRUE(fd->fd);
  EXPECT_TRUE(fd->bit_rate_switch);
  EXPECT_EQ(fd->id, 0x12345678u);
  EXPECT_EQ(fd->length, 4);
  EXPECT_EQ(fd->data[3], 0xEF);
  const auto remote = ParseCanFrame("7FF#R8");
  ASSERT_TRUE(remote.has_value());
  EXPECT_TRUE(remote->remote);
  EXPECT_EQ(remote->length, 8);
}

TEST(CanFrameTextTest, RejectsMalformedText) {
  for (const char* text :
       {"", "123", "12#00", "800#00", "20000000#00", "123#0", "123#GG", "123#001122334455667788",
        "123##", "123##1001122334455667788", "123#R9", "123#RX"}) {
    EXPECT_FALSE(ParseCanFrame(text).has_value()) << text;
  }
}

TEST(CanFrameTextTest, FormatRefusesASmallBuffer) {
  const auto frame = ParseCanFrame("123#DEADBEEF");
  ASSERT_TRUE(frame.has_value());
  char small[8];
  EXPECT_EQ(FormatCanFrame(*frame, small), 0u);
  char enough[13];
  EXPECT_EQ(FormatCanFrame(*frame, enough), 12u);
  EXPECT_EQ(std::string(enough), "123#DEADBEEF");
}

}  // namespace
}  // namespace hrgbench::hw
