// The Parameter command and the compensation parameter block against golden_frames.py (beside this
// file), which writes them from the README independently: the frames with its own CRC-8, the block
// with Python's struct (binary64, little-endian) and zlib.crc32 (IEEE 802.3), not this codec.

#include "gyro_can/parameter_block.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

#include "can_frame_assertions.hpp"
#include "gyro_can/gyro_codec.hpp"
#include "hrgbench/hw/can_frame_text.hpp"

namespace hrgbench::drivers::gyro_can {
namespace {

hw::CanFrame Frame(const char* text) { return testing::FrameFromText(text); }

constexpr ParameterValues kValues = {-1e-3, 0.29,  3e-5,   -2e-5, 2e-4,  -1e-4,
                                     0.01,  0.002, -0.003, 0.004, 1.5e-6};
constexpr const char* kGoldenWords =
    "0001 000B A9FC D2F1 624D BF50 C28F 28F5 8F5C 3FD2 1D69 4D55 7510 3EFF 68F1 88E3 F8B5 BEF4 "
    "432D EB1C 36E2 3F2A 432D EB1C 36E2 BF1A 147B 47AE 7AE1 3F84 A9FC D2F1 624D 3F60 7EFA BC6A "
    "9374 BF68 A9FC D2F1 624D 3F70 E454 7110 2A73 3EB9 C9FF 1CF2";

ParameterBlockWords Golden() {
  ParameterBlockWords words{};
  std::istringstream in(kGoldenWords);
  for (auto& w : words) in >> std::hex >> w;
  EXPECT_FALSE(in.fail());
  return words;
}

TEST(ParameterBlockTest, Crc32MatchesTheCatalogueCheckValue) {
  const char* check = "123456789";
  EXPECT_EQ(Crc32(reinterpret_cast<const std::uint8_t*>(check), std::strlen(check)), 0xCBF43926u);
}

TEST(ParameterBlockTest, EncodesTheGoldenBlockAndDecodesItBitForBit) {
  EXPECT_EQ(EncodeParameterBlock(kValues), Golden());
  ParameterValues decoded{};
  ASSERT_EQ(DecodeParameterBlock(Golden(), &decoded), ParameterBlockStatus::kOk);
  for (std::size_t i = 0; i < kValues.size(); ++i) EXPECT_EQ(decoded[i], kValues[i]) << i;
}

TEST(ParameterBlockTest, RefusesEveryDamagedBlockAndSaysHow) {
  ParameterValues out{};
  for (int i = 0; i < kParameterBlockWords; ++i) {
    ParameterBlockWords words = Golden();
    words[static_cast<std::size_t>(i)] ^= 0x0100;  // one bit flipped anywhere
    const ParameterBlockStatus status = DecodeParameterBlock(words, &out);
    EXPECT_NE(status, ParameterBlockStatus::kOk) << "word " << i;
    const ParameterBlockStatus expected = i == 0   ? ParameterBlockStatus::kBadLayout
                                          : i == 1 ? ParameterBlockStatus::kBadCount
                                                   : ParameterBlockStatus::kBadCrc;
    EXPECT_EQ(status, expected) << "word " << i;
  }
  ParameterValues with_nan = kValues;
  with_nan[4] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(DecodeParameterBlock(EncodeParameterBlock(with_nan), &out),
            ParameterBlockStatus::kNotFinite);
  EXPECT_EQ(ToString(ParameterBlockStatus::kBadCrc), "CRC-32 mismatch");
}

TEST(ParameterBlockTest, ParameterCommandGolden) {
  EXPECT_EQ(hw::CanFrameToString(EncodeParameter(0, {0x0C, ParameterOp::kBegin, 0, 48})),
            "030#0C010030000000CC");
  EXPECT_EQ(hw::CanFrameToString(EncodeParameter(6, {0x0D, ParameterOp::kWrite, 17, 0xBEEF})),
            "036#0D0211EFBE000091");
  EXPECT_EQ(hw::CanFrameToString(EncodeParameter(0, {0x0E, ParameterOp::kCommit, 0, 0})),
            "030#0E0500000000001C");
  const Ack read{Command::kParameter, 0x0F, AckResult::kOk, hw::GyroMode::kConfigured,
                 (17u << 16) | 0xBEEFu};
  EXPECT_EQ(hw::CanFrameToString(EncodeAck(0, read)), "080#450F0001EFBE111F");

  ParameterCommand decoded;
  ASSERT_EQ(DecodeParameter(Frame("036#0D0211EFBE000091"), 6, &decoded), DecodeStatus::kOk);
  EXPECT_EQ(decoded.token, 0x0D);
  EXPECT_EQ(decoded.op, ParameterOp::kWrite);
  EXPECT_EQ(decoded.index, 17);
  EXPECT_EQ(decoded.value, 0xBEEF);
  EXPECT_EQ(DecodeParameter(Frame("036#0D0211EFBE000091"), 0, &decoded), DecodeStatus::kWrongId);
  // An unknown operation, a reserved byte set: bad values (CRC recomputed so only that is wrong).
  hw::CanFrame bad_op = EncodeParameter(0, {1, ParameterOp::kWrite, 0, 0});
  bad_op.data[1] = 7;
  bad_op.data[7] = Crc8(bad_op.id, bad_op.data.data(), 7);
  EXPECT_EQ(DecodeParameter(bad_op, 0, &decoded), DecodeStatus::kBadValue);
  hw::CanFrame reserved = EncodeParameter(0, {1, ParameterOp::kWrite, 0, 0});
  reserved.data[6] = 1;
  reserved.data[7] = Crc8(reserved.id, reserved.data.data(), 7);
  EXPECT_EQ(DecodeParameter(reserved, 0, &decoded), DecodeStatus::kBadValue);
  EXPECT_TRUE(IsCommandId(0x036));
  EXPECT_FALSE(IsElectronicsId(0x036));
}

}  // namespace
}  // namespace hrgbench::drivers::gyro_can
