// Each sample carries the conditions of the electronics' last status report decoded before it was
// completed (issue 26 §4: temperature and frequency over each run): a report between two samples
// changes the later one only; a report between a sample's two frames belongs to that sample (it
// was completed after it); the reports before a release stamp the run's first samples; before any
// report the conditions are NaN. Determined by the order of the frames alone, so a replay of the
// CAN log stamps the same.
//
// Provenance: a synthetic stream written here (sample k's channel c = k + c LSB), and made-up
// status values; no randomness.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "gyro_can/gyro_codec.hpp"
#include "gyro_can/sample_stream_decoder.hpp"

namespace hrgbench::drivers::gyro_can {
namespace {

constexpr std::uint32_t kRateHz = 1000;
constexpr std::int64_t kT0Ns = 5'000'000'000;

void Half(SampleStreamDecoder& decoder, std::uint64_t k, std::uint8_t which) {
  SampleHalf half;
  half.half = which;
  half.seq = static_cast<std::uint8_t>(k % kClassicSeqModulo);
  half.y_raw = {static_cast<std::int32_t>(k + 2 * which),
                static_cast<std::int32_t>(k + 2 * which + 1)};
  decoder.OnSampleHalf(half, kT0Ns + static_cast<std::int64_t>(k) * 1'000'000 + 100'000);
}

void Whole(SampleStreamDecoder& decoder, std::uint64_t k) {
  Half(decoder, k, 0);
  Half(decoder, k, 1);
}

std::vector<hw::GyroSample> PopAll(SampleStreamDecoder& decoder) {
  std::vector<hw::GyroSample> out(64);
  out.resize(decoder.Pop(out));
  return out;
}

TEST(SampleStreamConditions, EachSampleCarriesTheLastStatusDecodedBeforeItWasWhole) {
  SampleStreamDecoder decoder(64);
  decoder.Start(FrameFormat::kClassic, kRateHz);
  decoder.SetReleaseTime(kT0Ns);
  Whole(decoder, 0);                // before any report: NaN
  decoder.OnStatus(25.25, 4999.5);  // between samples 0 and 1
  Whole(decoder, 1);
  Whole(decoder, 2);
  Half(decoder, 3, 0);
  decoder.OnStatus(25.26, 4999.499);  // between sample 3's two frames: sample 3 is whole after it
  Half(decoder, 3, 1);
  const auto samples = PopAll(decoder);
  ASSERT_EQ(samples.size(), 4u);
  EXPECT_TRUE(std::isnan(samples[0].temperature_c));
  EXPECT_TRUE(std::isnan(samples[0].resonant_frequency_hz));
  for (int k : {1, 2}) {
    EXPECT_EQ(samples[k].temperature_c, 25.25) << k;
    EXPECT_EQ(samples[k].resonant_frequency_hz, 4999.5) << k;
  }
  EXPECT_EQ(samples[3].temperature_c, 25.26);
  EXPECT_EQ(samples[3].resonant_frequency_hz, 4999.499);
  // The samples themselves are untouched by the reports.
  for (std::size_t k = 0; k < samples.size(); ++k) {
    EXPECT_EQ(samples[k].seq, k);
    EXPECT_EQ(samples[k].y[0], DequantiseY(static_cast<std::int32_t>(k)));
  }
}

TEST(SampleStreamConditions, TheReportBeforeAReleaseStampsTheRunsFirstSamples) {
  SampleStreamDecoder decoder(64);
  decoder.Start(FrameFormat::kClassic, kRateHz);
  decoder.SetReleaseTime(kT0Ns);
  decoder.OnStatus(24.0, 5000.0);
  Whole(decoder, 0);
  ASSERT_EQ(PopAll(decoder).size(), 1u);
  // The next run: the status polled while waiting for the wave, then the release.
  decoder.OnStatus(24.5, 5000.25);
  decoder.Start(FrameFormat::kClassic, kRateHz);
  decoder.SetReleaseTime(kT0Ns);
  Whole(decoder, 0);
  Whole(decoder, 1);
  const auto samples = PopAll(decoder);
  ASSERT_EQ(samples.size(), 2u);
  for (const hw::GyroSample& s : samples) {
    EXPECT_EQ(s.temperature_c, 24.5);
    EXPECT_EQ(s.resonant_frequency_hz, 5000.25);
  }
}

}  // namespace
}  // namespace hrgbench::drivers::gyro_can
