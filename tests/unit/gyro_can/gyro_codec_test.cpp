// Golden frames of the HRG CAN protocol v2 in can-utils notation. The expected texts were written
// from the README's message table by golden_frames.py (beside this file: an independent CRC-8 in
// Python, checked against the catalogue value CRC-8/SAE-J1850("123456789") = 0x4B), not produced
// by this codec. Node 0's Configure and SampleA kept version 1's identifiers, and their frames are
// version 1's golden frames unchanged.

#include "gyro_can/gyro_codec.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iterator>
#include <numbers>
#include <set>
#include <string>

#include "can_frame_assertions.hpp"
#include "hrgbench/hw/can_frame_text.hpp"

namespace hrgbench::drivers::gyro_can {
namespace {

hw::CanFrame Frame(const char* text) { return testing::FrameFromText(text); }

TEST(GyroCodecTest, CrcMatchesTheCatalogueCheckValue) {
  // The id bytes are fed first (little-endian): id 0x3231 contributes "1", "2".
  const std::uint8_t rest[] = {'3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(Crc8(0x3231, rest, sizeof rest), 0x4B);
}

TEST(GyroCodecTest, ConfigureGolden) {
  ConfigureCommand command;
  command.token = 0x07;
  command.sample_rate_hz = 1000;
  command.format = FrameFormat::kClassic;
  command.status_rate_hz = 10;
  EXPECT_EQ(hw::CanFrameToString(EncodeConfigure(0, command)), "040#07E803000A0000E9");
  EXPECT_EQ(hw::CanFrameToString(EncodeConfigure(5, command)), "045#07E803000A000005");
  ConfigureCommand fd{
      .token = 0x21, .sample_rate_hz = 5000, .format = FrameFormat::kFd, .status_rate_hz = 0};
  EXPECT_EQ(hw::CanFrameToString(EncodeConfigure(0, fd)), "040#2188130100000051");

  ConfigureCommand decoded;
  ASSERT_EQ(DecodeConfigure(Frame("040#2188130100000051"), 0, &decoded), DecodeStatus::kOk);
  EXPECT_EQ(decoded.token, 0x21);
  EXPECT_EQ(decoded.sample_rate_hz, 5000);
  EXPECT_EQ(decoded.format, FrameFormat::kFd);
  EXPECT_EQ(decoded.status_rate_hz, 0);
}

TEST(GyroCodecTest, OperatingModeGolden) {
  // Configure's byte 5 starts the operating mode at Release; run mode 0 is version 1's frame.
  const ConfigureCommand whole_angle{.token = 0x10,
                                     .sample_rate_hz = 1000,
                                     .format = FrameFormat::kClassic,
                                     .status_rate_hz = 10,
                                     .run_mode = RunMode::kWholeAngle};
  EXPECT_EQ(hw::CanFrameToString(EncodeConfigure(0, whole_angle)), "040#10E803000A010092");
  ConfigureCommand decoded;
  ASSERT_EQ(DecodeConfigure(Frame("040#10E803000A010092"), 0, &decoded), DecodeStatus::kOk);
  EXPECT_EQ(decoded.run_mode, RunMode::kWholeAngle);
  // The angle output −3 rad, the wave angle π/2.
  const OperatingSampleFrame sample{
      .seq = 0x2A, .angle_output_raw = -3 * 2097152, .wave_angle_raw = 32768};
  EXPECT_EQ(hw::CanFrameToString(EncodeOperatingSample(4, sample)), "144#2A0000A0FF008082");
  OperatingSampleFrame read;
  ASSERT_EQ(DecodeOperatingSample(Frame("144#2A0000A0FF008082"), 4, &read), DecodeStatus::kOk);
  EXPECT_EQ(read.seq, 0x2A);
  EXPECT_DOUBLE_EQ(read.angle_output_raw * kAngleOutputLsbRad, -3.0);
  EXPECT_DOUBLE_EQ(read.wave_angle_raw * kWaveAngleLsbRad, std::numbers::pi / 2);
  EXPECT_TRUE(IsElectronicsId(0x144));
}

TEST(GyroCodecTest, OperatingLoopsGolden) {
  // Sample 0x2A's report, node 3: the energy error 2e-4 and K̂/Ŝ = −3e-7 (A), g = 1e-3 1/s and
  // q = −1.5e-4 rad/s (B); golden_frames.py's loopsA3, loopsB3 and loopsA0sat.
  const OperatingLoopsHalf a{.half = 0,
                             .seq = 0x2A,
                             .value_raw = {QuantiseLoopValue(2e-4, kEnergyErrorLsb),
                                           QuantiseLoopValue(-3e-7, kQuadratureRatioLsb)}};
  const OperatingLoopsHalf b{.half = 1,
                             .seq = 0x2A,
                             .value_raw = {QuantiseLoopValue(1e-3, kLoopEffortLsb),
                                           QuantiseLoopValue(-1.5e-4, kLoopEffortLsb)}};
  EXPECT_EQ(hw::CanFrameToString(EncodeOperatingLoopsHalf(3, a)), "153#2AB7D100DEEBFF2B");
  EXPECT_EQ(hw::CanFrameToString(EncodeOperatingLoopsHalf(3, b)), "163#2A250601AED8FFA8");
  // Values beyond the fields' ranges saturate at the int24 bounds (K̂/Ŝ of a wave out of lock).
  const OperatingLoopsHalf saturated{.half = 0,
                                     .seq = 0xFF,
                                     .value_raw = {QuantiseLoopValue(1.0, kEnergyErrorLsb),
                                                   QuantiseLoopValue(-1.0, kQuadratureRatioLsb)}};
  EXPECT_EQ(hw::CanFrameToString(EncodeOperatingLoopsHalf(0, saturated)), "150#FFFFFF7F000080E3");

  OperatingLoopsHalf read;
  ASSERT_EQ(DecodeOperatingLoopsHalf(Frame("153#2AB7D100DEEBFF2B"), 3, &read), DecodeStatus::kOk);
  EXPECT_EQ(read.half, 0);
  EXPECT_EQ(read.seq, 0x2A);
  EXPECT_NEAR(read.value_raw[0] * kEnergyErrorLsb, 2e-4, kEnergyErrorLsb / 2);
  EXPECT_NEAR(read.value_raw[1] * kQuadratureRatioLsb, -3e-7, kQuadratureRatioLsb / 2);
  ASSERT_EQ(DecodeOperatingLoopsHalf(Frame("163#2A250601AED8FFA8"), 3, &read), DecodeStatus::kOk);
  EXPECT_EQ(read.half, 1);
  EXPECT_NEAR(read.value_raw[0] * kLoopEffortLsb, 1e-3, kLoopEffortLsb / 2);
  EXPECT_NEAR(read.value_raw[1] * kLoopEffortLsb, -1.5e-4, kLoopEffortLsb / 2);
  EXPECT_TRUE(IsElectronicsId(0x153));
  EXPECT_TRUE(IsElectronicsId(0x16F));
  EXPECT_FALSE(IsCommandId(0x163));
}

TEST(GyroCodecTest, OperatingLoopsRoundTripWithinHalfAnLsbAndSaturate) {
  // What the loops hold, locked and noisy: K̂/Ŝ 1e-9 … 1e-4, g ≈ 1e-3 1/s, q ≈ 1e-4 rad/s.
  for (const double ratio : {1e-9, -3.3e-8, 7e-6, -1e-4, 4.8e-4}) {
    for (const double effort : {1e-3, -2.7e-4, 1.1e-4, 0.1}) {
      const OperatingLoopsHalf a{.half = 0,
                                 .seq = 200,
                                 .value_raw = {QuantiseLoopValue(-effort / 8, kEnergyErrorLsb),
                                               QuantiseLoopValue(ratio, kQuadratureRatioLsb)}};
      const OperatingLoopsHalf b{.half = 1,
                                 .seq = 200,
                                 .value_raw = {QuantiseLoopValue(effort, kLoopEffortLsb),
                                               QuantiseLoopValue(-effort, kLoopEffortLsb)}};
      OperatingLoopsHalf a2, b2;
      ASSERT_EQ(DecodeOperatingLoopsHalf(EncodeOperatingLoopsHalf(11, a), 11, &a2),
                DecodeStatus::kOk);
      ASSERT_EQ(DecodeOperatingLoopsHalf(EncodeOperatingLoopsHalf(11, b), 11, &b2),
                DecodeStatus::kOk);
      EXPECT_EQ(a2.half, 0);
      EXPECT_EQ(b2.half, 1);
      EXPECT_EQ(a2.seq, 200);
      EXPECT_LE(std::abs(a2.value_raw[0] * kEnergyErrorLsb + effort / 8), kEnergyErrorLsb / 2);
      EXPECT_LE(std::abs(a2.value_raw[1] * kQuadratureRatioLsb - ratio), kQuadratureRatioLsb / 2);
      EXPECT_LE(std::abs(b2.value_raw[0] * kLoopEffortLsb - effort), kLoopEffortLsb / 2);
      EXPECT_LE(std::abs(b2.value_raw[1] * kLoopEffortLsb + effort), kLoopEffortLsb / 2);
    }
  }
  // The fields' bounds: ±2^23 LSB, saturating beyond; NaN is 0; an out-of-range raw value given
  // to the encoder is clamped, never wrapped into the other sign.
  EXPECT_EQ(QuantiseLoopValue(1e-3, kQuadratureRatioLsb), kLoopsRawMax);
  EXPECT_EQ(QuantiseLoopValue(-1e-3, kQuadratureRatioLsb), kLoopsRawMin);
  EXPECT_EQ(QuantiseLoopValue(std::nan(""), kLoopEffortLsb), 0);
  EXPECT_EQ(QuantiseLoopValue(0.125 - kLoopEffortLsb, kLoopEffortLsb), kLoopsRawMax);
  EXPECT_EQ(QuantiseLoopValue(-0.125, kLoopEffortLsb), kLoopsRawMin);
  OperatingLoopsHalf clamped;
  ASSERT_EQ(
      DecodeOperatingLoopsHalf(
          EncodeOperatingLoopsHalf(0, {.half = 1, .seq = 0, .value_raw = {1 << 24, -(1 << 24)}}), 0,
          &clamped),
      DecodeStatus::kOk);
  EXPECT_EQ(clamped.value_raw[0], kLoopsRawMax);
  EXPECT_EQ(clamped.value_raw[1], kLoopsRawMin);
}

TEST(GyroCodecTest, OperatingLoopsRefusesACorruptedOrForeignFrame) {
  OperatingLoopsHalf read;
  const hw::CanFrame good = Frame("163#2A250601AED8FFA8");
  // Every single-bit flip of the payload or the CRC is caught.
  for (int bit = 0; bit < 64; ++bit) {
    hw::CanFrame bad = good;
    bad.data[static_cast<std::size_t>(bit / 8)] ^= static_cast<std::uint8_t>(1u << (bit % 8));
    EXPECT_EQ(DecodeOperatingLoopsHalf(bad, 3, &read), DecodeStatus::kBadChecksum) << "bit " << bit;
  }
  // The CRC covers the identifier: the same payload as the other half's is refused.
  hw::CanFrame other_half = good;
  other_half.id = 0x153;
  EXPECT_EQ(DecodeOperatingLoopsHalf(other_half, 3, &read), DecodeStatus::kBadChecksum);
  EXPECT_EQ(DecodeOperatingLoopsHalf(good, 4, &read), DecodeStatus::kWrongId);
  EXPECT_EQ(DecodeOperatingLoopsHalf(Frame("143#2A250601AED8FFA8"), 3, &read),
            DecodeStatus::kWrongId);
  EXPECT_EQ(DecodeOperatingLoopsHalf(Frame("163#2A250601AED8FF"), 3, &read),
            DecodeStatus::kWrongLength);
  EXPECT_EQ(DecodeOperatingLoopsHalf(Frame("163##02A250601AED8FFA8"), 3, &read),
            DecodeStatus::kWrongKind);
  EXPECT_EQ(DecodeOperatingLoopsHalf(Frame("163#R"), 3, &read), DecodeStatus::kWrongKind);
}

TEST(GyroCodecTest, ExciteGolden) {
  // a = 1, b = -0.4, θ = π/7 (the paper's run 2 design) in 1e-4 units.
  ExciteCommand command{.token = 0x08, .a_raw = 10000, .b_raw = -4000, .theta_raw = 4488};
  EXPECT_EQ(hw::CanFrameToString(EncodeExcite(0, command)), "050#08102760F0881103");
  EXPECT_EQ(hw::CanFrameToString(EncodeExcite(3, command)), "053#08102760F08811AC");
  ExciteCommand decoded;
  ASSERT_EQ(DecodeExcite(Frame("053#08102760F08811AC"), 3, &decoded), DecodeStatus::kOk);
  EXPECT_EQ(decoded.a_raw, 10000);
  EXPECT_EQ(decoded.b_raw, -4000);
  EXPECT_EQ(decoded.theta_raw, 4488);
  EXPECT_NEAR(decoded.theta_raw * kExciteLsb, std::numbers::pi / 7, kExciteLsb / 2);
}

TEST(GyroCodecTest, SimpleCommandsGolden) {
  EXPECT_EQ(hw::CanFrameToString(EncodeSimpleCommand(0, {Command::kRelease, 0x09})), "060#0954");
  EXPECT_EQ(hw::CanFrameToString(EncodeSimpleCommand(0, {Command::kStop, 0x0A})), "020#0A13");
  EXPECT_EQ(hw::CanFrameToString(EncodeSimpleCommand(15, {Command::kStop, 0x0A})), "02F#0A95");
  EXPECT_EQ(hw::CanFrameToString(EncodeSimpleCommand(0, {Command::kStatusRequest, 0x0B})),
            "070#0B76");
  SimpleCommand decoded;
  ASSERT_EQ(DecodeSimpleCommand(Frame("02F#0A95"), 15, &decoded), DecodeStatus::kOk);
  EXPECT_EQ(decoded.command, Command::kStop);
  EXPECT_EQ(decoded.token, 0x0A);
  EXPECT_EQ(DecodeSimpleCommand(Frame("050#0A13"), 0, &decoded), DecodeStatus::kWrongId);
  // Node 15's Stop is not node 0's.
  EXPECT_EQ(DecodeSimpleCommand(Frame("02F#0A95"), 0, &decoded), DecodeStatus::kWrongId);
}

TEST(GyroCodecTest, AckGolden) {
  const Ack release{Command::kRelease, 0x09, AckResult::kOk, hw::GyroMode::kFreeRun, 0};
  EXPECT_EQ(hw::CanFrameToString(EncodeAck(5, release)), "085#4209000400000006");
  const Ack configure{Command::kConfigure, 0x07, AckResult::kOk, hw::GyroMode::kConfigured, 1000};
  EXPECT_EQ(hw::CanFrameToString(EncodeAck(0, configure)), "080#40070001E8030048");
  Ack decoded;
  ASSERT_EQ(DecodeAck(Frame("080#410801000000006F"), 0, &decoded), DecodeStatus::kOk);
  EXPECT_EQ(decoded.command, Command::kExcite);
  EXPECT_EQ(decoded.token, 0x08);
  EXPECT_EQ(decoded.result, AckResult::kBadState);
  EXPECT_EQ(decoded.mode, hw::GyroMode::kIdle);
}

TEST(GyroCodecTest, StatusGolden) {
  const StatusMessage status{.mode = hw::GyroMode::kReady,
                             .pll_lock = true,
                             .ready = true,
                             .fault_bits = 0,
                             .frequency_mhz = 5123456,
                             .temperature_centi_c = 2537};
  EXPECT_EQ(hw::CanFrameToString(EncodeStatus(0, status)), "090#3300802D4EE90959");
  StatusMessage decoded;
  ASSERT_EQ(DecodeStatusMessage(Frame("097#060558474C1EFBC3"), 7, &decoded), DecodeStatus::kOk);
  EXPECT_EQ(decoded.mode, hw::GyroMode::kFaulted);
  EXPECT_FALSE(decoded.pll_lock);
  EXPECT_EQ(decoded.fault_bits, hw::gyro_fault::kPllUnlock | hw::gyro_fault::kExciteTimeout);
  EXPECT_EQ(decoded.frequency_mhz, 4999000u);
  EXPECT_EQ(decoded.temperature_centi_c, -1250);
}

TEST(GyroCodecTest, SampleHalvesGolden) {
  SampleHalf a{.half = 0, .seq = 0x2A, .y_raw = {QuantiseY(1.0), QuantiseY(-0.5)}};
  SampleHalf b{.half = 1, .seq = 0x2A, .y_raw = {QuantiseY(0.25), QuantiseY(-kSampleLsb)}};
  EXPECT_EQ(hw::CanFrameToString(EncodeSampleHalf(0, a)), "100#2A0000400000E002");
  EXPECT_EQ(hw::CanFrameToString(EncodeSampleHalf(0, b)), "110#2A000010FFFFFF94");
  EXPECT_EQ(hw::CanFrameToString(EncodeSampleHalf(2, a)), "102#2A0000400000E0C8");
  // Saturation at ±full scale.
  SampleHalf sat{.half = 0, .seq = 0xFF, .y_raw = {QuantiseY(5.0), QuantiseY(-5.0)}};
  EXPECT_EQ(hw::CanFrameToString(EncodeSampleHalf(0, sat)), "100#FFFFFF7F00008085");

  SampleHalf decoded;
  ASSERT_EQ(DecodeSampleHalf(Frame("110#2A000010FFFFFF94"), 0, &decoded), DecodeStatus::kOk);
  EXPECT_EQ(decoded.half, 1);
  EXPECT_EQ(decoded.seq, 0x2A);
  EXPECT_EQ(DequantiseY(decoded.y_raw[0]), 0.25);
  EXPECT_EQ(DequantiseY(decoded.y_raw[1]), -kSampleLsb);
}

TEST(GyroCodecTest, ReferencePhaseGolden) {
  // χ = 1 rad: 2^32/(2π) = 683 565 275.6 → 0x28BE60DC; χ = −0.5 rad wraps to 2π − 0.5. The CRC
  // bytes were computed independently (a Python J1850 CRC-8 over id LE + payload).
  EXPECT_EQ(QuantiseReferencePhase(1.0), 0x28BE60DCu);
  EXPECT_EQ(QuantiseReferencePhase(-0.5), 0xEBA0CF92u);
  EXPECT_EQ(QuantiseReferencePhase(2 * std::numbers::pi), 0u);
  EXPECT_EQ(QuantiseReferencePhase(1.0 + 4 * std::numbers::pi), 0x28BE60DCu);
  EXPECT_EQ(hw::CanFrameToString(EncodeReferencePhase(0, {0x1234, QuantiseReferencePhase(1.0)})),
            "130#3412DC60BE2800A6");
  EXPECT_EQ(hw::CanFrameToString(EncodeReferencePhase(15, {0xFFFF, QuantiseReferencePhase(-0.5)})),
            "13F#FFFF92CFA0EB002C");
  ReferencePhaseReport decoded;
  ASSERT_EQ(DecodeReferencePhase(Frame("130#3412DC60BE2800A6"), 0, &decoded), DecodeStatus::kOk);
  EXPECT_EQ(decoded.seq, 0x1234);
  EXPECT_NEAR(DequantiseReferencePhase(decoded.phase_raw), 1.0, kReferencePhaseLsbRad);
  // The reserved byte must be 0 (CRC recomputed so that only the value is wrong).
  hw::CanFrame reserved = Frame("130#3412DC60BE2800A6");
  reserved.data[6] = 1;
  reserved.data[7] = Crc8(reserved.id, reserved.data.data(), 7);
  EXPECT_EQ(DecodeReferencePhase(reserved, 0, &decoded), DecodeStatus::kBadValue);
  EXPECT_EQ(DecodeReferencePhase(Frame("130#3412DC60BE2800A7"), 0, &decoded),
            DecodeStatus::kBadChecksum);
  EXPECT_EQ(DecodeReferencePhase(Frame("130#3412DC60BE2800"), 0, &decoded),
            DecodeStatus::kWrongLength);
}

SampleFdBlock Pattern(std::uint16_t seq, std::uint8_t count) {
  SampleFdBlock block{.seq = seq, .count = count, .y_raw = {}};
  for (int s = 0; s < count; ++s) {
    for (int c = 0; c < 4; ++c) {
      block.y_raw[static_cast<std::size_t>(s)][static_cast<std::size_t>(c)] =
          (s * 4 + c + 1) * 1000 * (c % 2 == 1 ? -1 : 1);
    }
  }
  return block;
}

TEST(GyroCodecTest, SampleFdGolden) {
  const char* full =
      "120##1341205E8030030F8FFB80B0060F0FF88130090E8FF581B00C0E0FF282300F0D8FFF82A0020D1FFC83200"
      "50C9FF983A0080C1FF684200B0B9FF384A00E0B1FF68";
  const char* partial =
      "129##1FFFF02E8030030F8FFB80B0060F0FF88130090E8FF581B00C0E0FF00000000000000000000000000000000"
      "0000000000000000000000000000000000000000DD";
  EXPECT_EQ(hw::CanFrameToString(EncodeSampleFd(0, Pattern(0x1234, 5))), full);
  EXPECT_EQ(hw::CanFrameToString(EncodeSampleFd(9, Pattern(0xFFFF, 2))), partial);
  SampleFdBlock decoded;
  ASSERT_EQ(DecodeSampleFd(Frame(partial), 9, &decoded), DecodeStatus::kOk);
  EXPECT_EQ(decoded.seq, 0xFFFF);
  EXPECT_EQ(decoded.count, 2);
  EXPECT_EQ(decoded.y_raw, Pattern(0xFFFF, 2).y_raw);
}

TEST(GyroCodecTest, RoundTripsEveryMessage) {
  for (int token = 0; token < 256; token += 51) {
    const auto t = static_cast<std::uint8_t>(token);
    ConfigureCommand configure{.token = t,
                               .sample_rate_hz = static_cast<std::uint16_t>(token * 37),
                               .format = FrameFormat::kFd,
                               .status_rate_hz = 3};
    ConfigureCommand c2;
    ASSERT_EQ(DecodeConfigure(EncodeConfigure(t % 16u, configure), t % 16u, &c2),
              DecodeStatus::kOk);
    EXPECT_EQ(c2.sample_rate_hz, configure.sample_rate_hz);
    const ExciteCommand excite{.token = t, .a_raw = 65535, .b_raw = -32768, .theta_raw = 32767};
    ExciteCommand e2;
    ASSERT_EQ(DecodeExcite(EncodeExcite(t % 16u, excite), t % 16u, &e2), DecodeStatus::kOk);
    EXPECT_EQ(e2.a_raw, 65535);
    EXPECT_EQ(e2.b_raw, -32768);
    EXPECT_EQ(e2.theta_raw, 32767);
    const Ack ack{Command::kStop, t, AckResult::kFaulted, hw::GyroMode::kStopped, 0xABCDEF};
    Ack a2;
    ASSERT_EQ(DecodeAck(EncodeAck(t % 16u, ack), t % 16u, &a2), DecodeStatus::kOk);
    EXPECT_EQ(a2.arg, 0xABCDEFu);
    EXPECT_EQ(a2.result, AckResult::kFaulted);
  }
  for (double y = -2.5; y <= 2.5; y += 0.0137) {
    const SampleHalf half{.half = 1, .seq = 200, .y_raw = {QuantiseY(y), QuantiseY(-y)}};
    SampleHalf h2;
    ASSERT_EQ(DecodeSampleHalf(EncodeSampleHalf(11, half), 11, &h2), DecodeStatus::kOk);
    if (std::abs(y) < 2.0 - kSampleLsb) {
      EXPECT_LE(std::abs(DequantiseY(h2.y_raw[0]) - y), kSampleLsb / 2);
      EXPECT_LE(std::abs(DequantiseY(h2.y_raw[1]) + y), kSampleLsb / 2);
    }
  }
}

TEST(GyroCodecTest, RejectsEveryKindOfBadFrame) {
  SampleHalf half;
  EXPECT_EQ(DecodeSampleHalf(Frame("100#2A0000400000E003"), 0, &half), DecodeStatus::kBadChecksum);
  EXPECT_EQ(DecodeSampleHalf(Frame("100#2A0000400000E0"), 0, &half), DecodeStatus::kWrongLength);
  EXPECT_EQ(DecodeSampleHalf(Frame("100#R"), 0, &half), DecodeStatus::kWrongKind);
  EXPECT_EQ(DecodeSampleHalf(Frame("00000100#2A0000400000E002"), 0, &half), DecodeStatus::kWrongId);
  EXPECT_EQ(DecodeSampleHalf(Frame("100##02A0000400000E002"), 0, &half), DecodeStatus::kWrongKind);
  // Every single-bit flip of a sample frame is caught (CRC-8 has Hamming distance ≥ 2).
  const hw::CanFrame good = Frame("100#2A0000400000E002");
  for (int bit = 0; bit < 64; ++bit) {
    hw::CanFrame bad = good;
    bad.data[static_cast<std::size_t>(bit / 8)] ^= static_cast<std::uint8_t>(1u << (bit % 8));
    EXPECT_EQ(DecodeSampleHalf(bad, 0, &half), DecodeStatus::kBadChecksum) << "bit " << bit;
  }
  // Undefined enumerated values with a valid CRC: a result of 7.
  Ack ack_in{Command::kStop, 1, AckResult::kOk, hw::GyroMode::kStopped, 0};
  hw::CanFrame bad_ack = EncodeAck(0, ack_in);
  bad_ack.data[2] = 7;
  bad_ack.data[7] = Crc8(bad_ack.id, bad_ack.data.data(), 7);
  Ack ack;
  EXPECT_EQ(DecodeAck(bad_ack, 0, &ack), DecodeStatus::kBadValue);
  SampleFdBlock block = Pattern(1, 5);
  hw::CanFrame bad_count = EncodeSampleFd(0, block);
  bad_count.data[2] = 6;
  bad_count.data[63] = Crc8(bad_count.id, bad_count.data.data(), 63);
  EXPECT_EQ(DecodeSampleFd(bad_count, 0, &block), DecodeStatus::kBadValue);
}

TEST(GyroCodecTest, NodeIdsNeverChangeWhichMessageWinsArbitration) {
  // Every node's Stop beats every node's other commands, every command beats every answer, every
  // answer beats every sample frame (README "Identifiers").
  const auto highest = [](std::uint32_t message) { return NodeMessageId(message, kMaxNodeId); };
  const auto lowest = [](std::uint32_t message) { return NodeMessageId(message, 0); };
  EXPECT_LT(highest(can_id::kStop), lowest(can_id::kConfigure));
  EXPECT_LT(highest(can_id::kStatusRequest), lowest(can_id::kAck));
  EXPECT_LT(highest(can_id::kStatus), lowest(can_id::kSampleA));
  EXPECT_LE(highest(can_id::kReferencePhase), 0x7FFu);
  // The angle output beats its loops' reports.
  EXPECT_LT(highest(can_id::kOperatingSample), lowest(can_id::kOperatingLoopsA));
  EXPECT_LE(highest(can_id::kOperatingLoopsB), 0x7FFu);
  // Distinct identifiers for every (message, node): 14 messages × 16 nodes.
  const std::uint32_t messages[] = {can_id::kStop,
                                    can_id::kConfigure,
                                    can_id::kExcite,
                                    can_id::kRelease,
                                    can_id::kStatusRequest,
                                    can_id::kAck,
                                    can_id::kStatus,
                                    can_id::kSampleA,
                                    can_id::kSampleB,
                                    can_id::kSampleFd,
                                    can_id::kReferencePhase,
                                    can_id::kOperatingSample,
                                    can_id::kOperatingLoopsA,
                                    can_id::kOperatingLoopsB};
  std::set<std::uint32_t> ids;
  for (const std::uint32_t message : messages) {
    for (int node = 0; node <= kMaxNodeId; ++node) {
      const std::uint32_t id = NodeMessageId(message, static_cast<NodeId>(node));
      ids.insert(id);
      EXPECT_EQ(NodeOf(id), node);
      EXPECT_EQ(MessageOf(id), message);
      EXPECT_NE(IsCommandId(id), IsElectronicsId(id)) << std::hex << id;
    }
  }
  EXPECT_EQ(ids.size(), std::size(messages) * 16u);
}

TEST(GyroCodecTest, AFrameOfAnotherNodeIsNotThisNodes) {
  const hw::CanFrame sample = EncodeSampleHalf(3, {.half = 0, .seq = 1, .y_raw = {1, 2}});
  SampleHalf half;
  EXPECT_EQ(DecodeSampleHalf(sample, 3, &half), DecodeStatus::kOk);
  EXPECT_EQ(DecodeSampleHalf(sample, 4, &half), DecodeStatus::kWrongId);
  const hw::CanFrame status = EncodeStatus(12, {});
  StatusMessage message;
  EXPECT_EQ(DecodeStatusMessage(status, 12, &message), DecodeStatus::kOk);
  EXPECT_EQ(DecodeStatusMessage(status, 2, &message), DecodeStatus::kWrongId);
}

}  // namespace
}  // namespace hrgbench::drivers::gyro_can
