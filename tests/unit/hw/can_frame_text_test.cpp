#include "hrgbench/hw/can_frame_text.hpp"

#include <gtest/gtest.h>

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
