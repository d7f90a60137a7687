// SampleStreamDecoder under lost frames and a late sender (issue 25 row 15): a lost frame costs a
// sample, never makes the data wrong. Every sample the decoder delivers is compared with the truth:
// its number, its four values (each a function of the number and the channel, so a pairing of one
// sample's SampleA with another's SampleB shows) and its time stamp t0 + k/fs. Losses at every
// frame position, runs of losses up to beyond two wraps of the 8-bit counter, and a sender that
// falls behind and catches up in a burst (what a starved emulated CPU does: its frames carry late
// receive stamps), with and without the tail of the burst lost in the receiver's queue.
//
// Provenance: the stream is synthetic, written here (value of channel c of sample k:
// ((k·7 + c·1 000 003) mod 2^23) LSB); no randomness.

#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "gyro_can/gyro_codec.hpp"
#include "gyro_can/sample_stream_decoder.hpp"

namespace hrgbench::drivers::gyro_can {
namespace {

constexpr std::uint32_t kRateHz = 500;  // the kernel end-to-end test's rate
constexpr std::int64_t kPeriodNs = 1'000'000'000 / kRateHz;
constexpr std::int64_t kT0Ns = 1'000'000'000'000;  // an arbitrary receive time base

std::int32_t Truth(std::uint64_t k, int channel) {
  return static_cast<std::int32_t>((k * 7 + static_cast<std::uint64_t>(channel) * 1'000'003) %
                                   (1u << 23));
}

// One sample frame as it reaches the decoder: sample k's half, received at stamp_ns.
struct Arrival {
  std::uint64_t sample = 0;
  std::uint8_t half = 0;
  std::int64_t stamp_ns = 0;
};

// Sample k's two frames, sent on time (received 0.1 ms after the sample is due).
std::vector<Arrival> OnTime(std::uint64_t samples) {
  std::vector<Arrival> frames;
  for (std::uint64_t k = 0; k < samples; ++k) {
    const std::int64_t due = kT0Ns + static_cast<std::int64_t>(k) * kPeriodNs + 100'000;
    frames.push_back({k, 0, due});
    frames.push_back({k, 1, due + 50'000});
  }
  return frames;
}

struct Outcome {
  std::vector<hw::GyroSample> samples;
  SampleStreamCounters counters;
};

Outcome Decode(const std::vector<Arrival>& frames) {
  SampleStreamDecoder decoder(frames.size() + 16);
  decoder.Start(FrameFormat::kClassic, kRateHz);
  decoder.SetReleaseTime(kT0Ns);
  for (const Arrival& a : frames) {
    SampleHalf half;
    half.half = a.half;
    half.seq = static_cast<std::uint8_t>(a.sample % kClassicSeqModulo);
    half.y_raw = {Truth(a.sample, 2 * a.half), Truth(a.sample, 2 * a.half + 1)};
    decoder.OnSampleHalf(half, a.stamp_ns);
  }
  Outcome out;
  out.samples.resize(frames.size() + 16);
  out.samples.resize(decoder.Pop(out.samples));
  out.counters = decoder.counters();
  return out;
}

// Every delivered sample is one that was sent whole (both its frames arrived), with its own four
// values and its own time; none is delivered twice. Returns the first discrepancy, or "".
std::string Check(const std::vector<Arrival>& frames, const Outcome& out) {
  std::set<std::uint64_t> whole, delivered;
  std::set<std::uint64_t> a_seen;
  for (const Arrival& f : frames) {
    if (f.half == 0) a_seen.insert(f.sample);
    if (f.half == 1 && a_seen.count(f.sample)) whole.insert(f.sample);
  }
  for (const hw::GyroSample& s : out.samples) {
    const std::string at = "sample delivered as " + std::to_string(s.seq);
    if (!whole.count(s.seq)) return at + ": no such whole sample was sent";
    if (!delivered.insert(s.seq).second) return at + ": delivered twice";
    for (int c = 0; c < 4; ++c) {
      if (s.y[c] != DequantiseY(Truth(s.seq, c))) {
        return at + ": channel " + std::to_string(c + 1) + " is another sample's value";
      }
    }
    const std::int64_t t_ns = kT0Ns + static_cast<std::int64_t>(s.seq) * kPeriodNs;
    if (s.t_ns != t_ns) return at + ": stamped " + std::to_string(s.t_ns - t_ns) + " ns off";
  }
  return "";
}

TEST(SampleStreamDrops, EveryStreamOnTimeIsWhole) {
  const auto frames = OnTime(1000);
  const Outcome out = Decode(frames);
  EXPECT_EQ(Check(frames, out), "");
  EXPECT_EQ(out.samples.size(), 1000u);
  EXPECT_EQ(out.counters.sequence_gaps, 0u);
  EXPECT_EQ(out.counters.samples_lost, 0u);
}

TEST(SampleStreamDrops, OneFrameLostAtEveryPositionCostsOneSample) {
  const auto all = OnTime(600);  // through two wraps of the counter
  // (The last frame's loss cannot show before the stream goes on.)
  for (std::size_t lost = 0; lost + 1 < all.size(); ++lost) {
    auto frames = all;
    frames.erase(frames.begin() + static_cast<std::ptrdiff_t>(lost));
    const Outcome out = Decode(frames);
    ASSERT_EQ(Check(frames, out), "") << "frame " << lost << " lost";
    ASSERT_EQ(out.samples.size(), 599u) << "frame " << lost << " lost";
    ASSERT_EQ(out.counters.sequence_gaps, 1u) << "frame " << lost << " lost";
    ASSERT_EQ(out.counters.samples_lost, 1u) << "frame " << lost << " lost";
  }
}

TEST(SampleStreamDrops, RunsOfLostFramesUpToBeyondTwoWrapsNeverMakeWrongSamples) {
  const auto all = OnTime(1600);
  for (std::size_t first : {0u, 1u, 2u, 3u, 254u, 255u, 256u, 511u, 512u, 513u}) {
    for (std::size_t count = 1; count <= 1100; count += (count < 20 ? 1 : 37)) {
      auto frames = all;
      frames.erase(frames.begin() + static_cast<std::ptrdiff_t>(first),
                   frames.begin() + static_cast<std::ptrdiff_t>(first + count));
      const Outcome out = Decode(frames);
      ASSERT_EQ(Check(frames, out), "") << count << " frames lost from " << first;
      ASSERT_GE(out.counters.sequence_gaps, 1u) << count << " frames lost from " << first;
      // Every sample is delivered or counted lost, while the counter can tell how many (a loss
      // shorter than three quarters of its wrap); beyond, the rest of the run is refused.
      const std::size_t accounted = out.samples.size() + out.counters.samples_lost;
      if (count < 384) {
        ASSERT_EQ(accounted, 1600u) << count << " frames lost from " << first;
      } else {
        ASSERT_GE(accounted + 256 * (count / 512 + 1), 1600u)  // whole wraps cannot be counted
            << count << " frames lost from " << first;
      }
    }
  }
}

// The sender is frozen for `stall_ms` after sample `from` and then sends what it owes at once:
// every frame of the burst carries the burst's receive stamp. The receiver's queue keeps only
// `kept` frames of the burst (the rest are kernel drops).
std::vector<Arrival> FrozenSender(std::uint64_t samples, std::uint64_t from, std::int64_t stall_ms,
                                  std::size_t kept) {
  std::vector<Arrival> frames;
  const std::int64_t wake =
      kT0Ns + static_cast<std::int64_t>(from) * kPeriodNs + stall_ms * 1'000'000;
  std::size_t in_burst = 0;
  for (std::uint64_t k = 0; k < samples; ++k) {
    const std::int64_t due = kT0Ns + static_cast<std::int64_t>(k) * kPeriodNs + 100'000;
    const bool burst = k >= from && due < wake;
    for (std::uint8_t half = 0; half < 2; ++half) {
      if (burst && in_burst++ >= kept) continue;
      frames.push_back({k, half, burst ? wake + static_cast<std::int64_t>(in_burst) * 1000 : due});
    }
  }
  return frames;
}

TEST(SampleStreamDrops, ALateSenderNeverShiftsItsSamples) {
  for (std::int64_t stall_ms : {100, 200, 300, 400, 500, 700, 1000, 1600}) {
    for (std::size_t kept : {std::size_t{100000}, std::size_t{400}, std::size_t{201},
                             std::size_t{70}, std::size_t{1}}) {
      const auto frames = FrozenSender(1500, 300, stall_ms, kept);
      const Outcome out = Decode(frames);
      ASSERT_EQ(Check(frames, out), "") << "stalled " << stall_ms << " ms, kept " << kept;
      // Nothing lost, nothing to lose: a stall alone costs no sample as long as the counter can
      // tell (a stall shorter than three quarters of its wrap, 384 ms at 500 Hz).
      if (kept == 100000 && stall_ms < 384) {
        EXPECT_EQ(out.samples.size(), 1500u) << "stalled " << stall_ms << " ms";
        EXPECT_EQ(out.counters.sequence_gaps, 0u) << "stalled " << stall_ms << " ms";
      }
      const auto burst_frames = static_cast<std::size_t>(stall_ms * kRateHz / 1000 * 2);
      if (burst_frames > kept + 2) {
        EXPECT_GE(out.counters.sequence_gaps, 1u) << "stalled " << stall_ms << " ms, kept " << kept;
      }
    }
  }
}

TEST(SampleStreamDrops, ARepeatedFrameIsNotTakenForAWrap) {
  auto frames = OnTime(800);
  frames.insert(frames.begin() + 301, frames[300]);  // CAN may deliver a frame twice
  const Outcome out = Decode(frames);
  EXPECT_EQ(Check(frames, out), "");
  EXPECT_GE(out.samples.size(), 798u);
}

}  // namespace
}  // namespace hrgbench::drivers::gyro_can
