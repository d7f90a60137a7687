// Seeded fuzzing of the gyro CAN protocol's receive side: random frames and bit-flipped valid
// frames into every decoder, the decoded sample frames (with random stamps, formats and rates)
// into SampleStreamDecoder, and random and mutated can-utils text into hw::ParseCanFrame. Nothing
// may crash; a decoder either says kOk, and then the frame re-encodes to one that decodes the same,
// or names what is wrong (a non-empty status text); the stream's counters stay consistent; text
// either parses to a frame that formats back to text parsing to the same frame, or is refused.
//
// Provenance: std::mt19937_64 seeded with kSeed (printed on failure with the iteration). 200 000
// frames and 100 000 texts, about 0.3 s.

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <iostream>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "fuzz_text.hpp"
#include "gyro_can/gyro_codec.hpp"
#include "gyro_can/sample_stream_decoder.hpp"
#include "hrgbench/hw/can_frame_text.hpp"

namespace hrgbench::drivers::gyro_can {
namespace {

constexpr std::uint64_t kSeed = 0xCA4F'2A3E'0001;
constexpr int kFrames = 200'000;
constexpr int kTexts = 100'000;

using hrgbench::testing::Draw;

bool SameFrame(const hw::CanFrame& a, const hw::CanFrame& b) {
  if (a.id != b.id || a.extended != b.extended || a.fd != b.fd || a.remote != b.remote ||
      a.error != b.error || a.length != b.length) {
    return false;
  }
  if (a.fd && a.bit_rate_switch != b.bit_rate_switch) return false;
  for (std::size_t i = 0; i < a.length && i < a.data.size() && !a.remote; ++i) {
    if (a.data[i] != b.data[i]) return false;
  }
  return true;
}

// A valid frame of a random message, for bit flips that get past the id and length checks.
hw::CanFrame ValidFrame(Draw& draw) {
  const auto byte = [&draw] { return static_cast<std::uint8_t>(draw.Bits()); };
  const auto node = static_cast<NodeId>(draw.Below(kMaxNodeId + 1u));
  switch (draw.Below(7)) {
    case 0:
      return EncodeConfigure(node,
                             {byte(), static_cast<std::uint16_t>(draw.Below(20'000)),
                              draw.OneIn(2) ? FrameFormat::kFd : FrameFormat::kClassic, byte()});
    case 1:
      return EncodeExcite(
          node, {byte(), static_cast<std::uint16_t>(draw.Bits()),
                 static_cast<std::int16_t>(draw.Bits()), static_cast<std::int16_t>(draw.Bits())});
    case 2:
      return EncodeSimpleCommand(node, {Command::kRelease, byte()});
    case 3:
      return EncodeAck(node, {Command::kExcite, byte(), AckResult::kOk, hw::GyroMode::kIdle,
                              static_cast<std::uint32_t>(draw.Bits())});
    case 4: {
      StatusMessage status;
      status.fault_bits = byte();
      status.frequency_mhz = static_cast<std::uint32_t>(draw.Below(1u << 24));
      status.temperature_centi_c = static_cast<std::int16_t>(draw.Bits());
      return EncodeStatus(node, status);
    }
    case 5:
      return EncodeSampleHalf(
          node,
          {static_cast<std::uint8_t>(draw.Below(2)), byte(), {QuantiseY(1.0), QuantiseY(-0.5)}});
    default: {
      SampleFdBlock block;
      block.seq = static_cast<std::uint16_t>(draw.Bits());
      block.count = static_cast<std::uint8_t>(1 + draw.Below(kSamplesPerFdFrame));
      return EncodeSampleFd(node, block);
    }
  }
}

hw::CanFrame RandomFrame(Draw& draw) {
  // A quarter valid as sent (the stream sees whole runs of samples), a quarter bit-flipped (the
  // CRC, length and kind checks), half random.
  if (draw.OneIn(4)) return ValidFrame(draw);
  if (draw.OneIn(3)) {
    hw::CanFrame frame = ValidFrame(draw);
    const std::size_t flips = 1 + draw.Below(3);
    for (std::size_t f = 0; f < flips; ++f) {
      switch (draw.Below(4)) {
        case 0:
          if (frame.length > 0)
            frame.data[draw.Below(frame.length)] ^= static_cast<std::uint8_t>(1u << draw.Below(8));
          break;
        case 1:
          frame.length = static_cast<std::uint8_t>(draw.Below(65));
          break;
        case 2:
          frame.id ^= 1u << draw.Below(11);
          break;
        default:
          frame.fd = !frame.fd;
          break;
      }
    }
    return frame;
  }
  hw::CanFrame frame;
  frame.extended = draw.OneIn(8);
  frame.id = static_cast<std::uint32_t>(draw.Bits()) &
             (frame.extended ? hw::CanFrame::kExtendedIdMask
                             : (draw.OneIn(2) ? 0x13Fu : hw::CanFrame::kStandardIdMask));
  frame.fd = draw.OneIn(3);
  frame.bit_rate_switch = draw.OneIn(2);
  frame.remote = draw.OneIn(16);
  frame.error = draw.OneIn(32);
  frame.length = static_cast<std::uint8_t>(draw.Below(256));  // also impossible lengths
  for (auto& b : frame.data) b = static_cast<std::uint8_t>(draw.Bits());
  return frame;
}

TEST(GyroCanFuzz, DecodersAndTheSampleStreamSurviveAnyFrame) {
  Draw draw(kSeed);
  SampleStreamDecoder stream(256);
  std::array<hw::GyroSample, 64> popped{};
  std::int64_t stamp_ns = 0;
  int decoded = 0;
  for (int iteration = 0; iteration < kFrames; ++iteration) {
    const std::string log =
        "seed " + std::to_string(kSeed) + " iteration " + std::to_string(iteration);
    if (draw.OneIn(500)) {
      stream.Start(
          draw.OneIn(2) ? FrameFormat::kFd : FrameFormat::kClassic,
          static_cast<std::uint32_t>(draw.OneIn(10) ? draw.Bits() : 1 + draw.Below(10'000)));
    }
    if (draw.OneIn(300)) stream.SetReleaseTime(static_cast<std::int64_t>(draw.Bits()));
    stamp_ns = draw.OneIn(100) ? static_cast<std::int64_t>(draw.Bits())
                               : stamp_ns + static_cast<std::int64_t>(draw.Below(2'000'000));
    const hw::CanFrame frame = RandomFrame(draw);

    // Each decoder, as the frame's node: kOk (then re-encode and decode again to the same frame)
    // or a named reason.
    const NodeId node = NodeOf(frame.id);
    const auto check = [&](auto decode, auto encode, auto message) {
      const DecodeStatus status = decode(frame, node, &message);
      ASSERT_FALSE(ToString(status).empty()) << log;
      ASSERT_NE(ToString(status), "?") << log;
      if (status != DecodeStatus::kOk) return;
      ++decoded;
      const hw::CanFrame again = encode(node, message);
      decltype(message) twice{};
      ASSERT_EQ(decode(again, node, &twice), DecodeStatus::kOk)
          << log << " " << hw::CanFrameToString(frame);
      ASSERT_TRUE(SameFrame(again, encode(node, twice)))
          << log << " " << hw::CanFrameToString(frame);
    };
    check(DecodeConfigure, EncodeConfigure, ConfigureCommand{});
    check(DecodeExcite, EncodeExcite, ExciteCommand{});
    check(DecodeSimpleCommand, EncodeSimpleCommand, SimpleCommand{});
    check(DecodeAck, EncodeAck, Ack{});
    check(DecodeStatusMessage, EncodeStatus, StatusMessage{});
    check(DecodeSampleHalf, EncodeSampleHalf, SampleHalf{});
    check(DecodeSampleFd, EncodeSampleFd, SampleFdBlock{});
    check(DecodeReferencePhase, EncodeReferencePhase, ReferencePhaseReport{});
    if (HasFatalFailure()) return;

    if (SampleHalf half; DecodeSampleHalf(frame, node, &half) == DecodeStatus::kOk) {
      stream.OnSampleHalf(half, stamp_ns);
    }
    if (SampleFdBlock block; DecodeSampleFd(frame, node, &block) == DecodeStatus::kOk) {
      stream.OnSampleFd(block, stamp_ns);
    }
    if (ReferencePhaseReport report;
        DecodeReferencePhase(frame, node, &report) == DecodeStatus::kOk) {
      stream.OnReferencePhase(report, stamp_ns);
    }
    ASSERT_LE(stream.Buffered(), 256u) << log;
    if (draw.OneIn(4)) {
      const std::size_t before = stream.Buffered();
      const std::size_t n = stream.Pop(std::span(popped).first(draw.Below(popped.size() + 1)));
      ASSERT_EQ(stream.Buffered(), before - n) << log;
    }
    const SampleStreamCounters& counters = stream.counters();
    ASSERT_LE(counters.sequence_gaps, counters.samples_lost + counters.samples_decoded + 1) << log;
  }
  EXPECT_GT(decoded, kFrames / 20) << "seed " << kSeed;
  std::cout << "seed " << kSeed << ": " << decoded << " decodes of " << kFrames << " frames\n";
}

TEST(GyroCanFuzz, FrameTextParsesOrIsRefused) {
  Draw draw(kSeed + 1);
  const std::string alphabet = "0123456789ABCDEFabcdef#R.xX-: \t\n\0";
  int parsed = 0;
  for (int iteration = 0; iteration < kTexts; ++iteration) {
    std::string text;
    if (draw.OneIn(2)) {  // a valid frame's text, mutated
      text = hw::CanFrameToString(ValidFrame(draw));
      const std::size_t edits = 1 + draw.Below(3);
      for (std::size_t e = 0; e < edits && !text.empty(); ++e) {
        const std::size_t at = draw.Below(text.size());
        switch (draw.Below(3)) {
          case 0:
            text[at] = alphabet[draw.Below(alphabet.size())];
            break;
          case 1:
            text.erase(at, 1 + draw.Below(4));
            break;
          default:
            text.insert(
                at, std::string(draw.OneIn(8) ? 200 : 1, alphabet[draw.Below(alphabet.size())]));
            break;
        }
      }
    } else {
      text.resize(draw.Below(160));
      for (char& c : text)
        c = draw.OneIn(4) ? static_cast<char>(draw.Bits()) : alphabet[draw.Below(alphabet.size())];
    }
    const std::optional<hw::CanFrame> frame = hw::ParseCanFrame(text);
    if (!frame) continue;
    ++parsed;
    const std::string again = hw::CanFrameToString(*frame);
    const std::optional<hw::CanFrame> reparsed = hw::ParseCanFrame(again);
    ASSERT_TRUE(reparsed) << "seed " << kSeed + 1 << " iteration " << iteration << ": " << again;
    ASSERT_TRUE(SameFrame(*frame, *reparsed)) << "iteration " << iteration << ": " << again;
  }
  EXPECT_GT(parsed, kTexts / 20) << "seed " << kSeed + 1;
  std::cout << "seed " << kSeed + 1 << ": " << parsed << " of " << kTexts << " texts parsed\n";
}

}  // namespace
}  // namespace hrgbench::drivers::gyro_can
