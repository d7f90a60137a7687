// SampleStreamDecoder with the reference-phase reports (frame 0x103): each sample turned back by χ
// interpolated between the reports around it, samples held until their report, electronics
// without reports unchanged, and a report that never comes bounded and counted.

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdint>
#include <numbers>
#include <vector>

#include "gyro_can/gyro_codec.hpp"
#include "gyro_can/sample_stream_decoder.hpp"

namespace hrgbench::drivers::gyro_can {
namespace {

constexpr double kPi = std::numbers::pi;

// What a reference kept locked would give: a slowly turning wave, (y1 + i·y2) = 0.8·e^{i·0.01k},
// (y3 + i·y4) = 0.3·e^{−i·0.02k}.
std::complex<double> Locked1(std::uint64_t k) {
  return std::polar(0.8, 0.01 * static_cast<double>(k));
}
std::complex<double> Locked2(std::uint64_t k) {
  return std::polar(0.3, -0.02 * static_cast<double>(k));
}
// The reference's phase: 0.2 rad per sample from 6 rad on (through 2π and on), i.e. 1 rad between
// reports, linear so that interpolation is exact.
double Chi(std::uint64_t k) { return 6.0 + 0.2 * static_cast<double>(k); }

// Sample k as the tracking electronics send it: e^{−iχ}·y_locked on both channels.
void SendSample(SampleStreamDecoder& stream, std::uint64_t k) {
  const std::complex<double> turn = std::polar(1.0, -Chi(k));
  const std::complex<double> u1 = turn * Locked1(k), u2 = turn * Locked2(k);
  const auto seq = static_cast<std::uint8_t>(k % kClassicSeqModulo);
  stream.OnSampleHalf({0, seq, {QuantiseY(u1.real()), QuantiseY(u1.imag())}}, 0);
  stream.OnSampleHalf({1, seq, {QuantiseY(u2.real()), QuantiseY(u2.imag())}}, 0);
}

void SendReport(SampleStreamDecoder& stream, std::uint64_t k) {
  stream.OnReferencePhase(
      {static_cast<std::uint16_t>(k % kFdSeqModulo), QuantiseReferencePhase(Chi(k))}, 0);
}

// The electronics' order: the report of every 5th sample, then that sample's frames.
void Send(SampleStreamDecoder& stream, std::uint64_t from, std::uint64_t to, bool reports) {
  for (std::uint64_t k = from; k < to; ++k) {
    if (reports && k % kReferencePhaseInterval == 0) SendReport(stream, k);
    SendSample(stream, k);
  }
}

TEST(ReferencePhaseStreamTest, SamplesAreTurnedBackByTheInterpolatedPhase) {
  SampleStreamDecoder stream(1024);
  stream.Start(FrameFormat::kClassic, 1000);
  Send(stream, 0, 600, true);  // 600 samples, χ from 6 to 125.8 rad (19 turns)
  std::vector<hw::GyroSample> out(1024);
  const std::size_t n = stream.Pop(out);
  // Every sample up to the last report (595) is out; 596..599 wait for the report at 600.
  ASSERT_EQ(n, 596u);
  EXPECT_EQ(stream.Buffered(), 4u);
  for (std::size_t i = 0; i < n; ++i) {
    const hw::GyroSample& s = out[i];
    ASSERT_EQ(s.seq, i);
    // χ as reported (mod 2π, to the phase word's LSB) ...
    EXPECT_NEAR(std::remainder(s.reference_phase_rad - Chi(i), 2 * kPi), 0.0, 1e-8) << i;
    // ... and y back on the locked reference's values, to the wire's quantisation (√2 LSB).
    EXPECT_NEAR(s.y[0], Locked1(i).real(), 4e-7) << i;
    EXPECT_NEAR(s.y[1], Locked1(i).imag(), 4e-7) << i;
    EXPECT_NEAR(s.y[2], Locked2(i).real(), 4e-7) << i;
    EXPECT_NEAR(s.y[3], Locked2(i).imag(), 4e-7) << i;
  }
  Send(stream, 600, 601, true);  // the report at 600 releases 596..600
  EXPECT_EQ(stream.Pop(out), 5u);
  EXPECT_EQ(out[4].seq, 600u);
  EXPECT_EQ(stream.counters().reference_phases_missing, 0u);
}

TEST(ReferencePhaseStreamTest, ALostReportIsBridgedByTheNextOne) {
  SampleStreamDecoder stream(1024);
  stream.Start(FrameFormat::kClassic, 1000);
  Send(stream, 0, 10, true);
  SendSample(stream, 10);  // the report of sample 10 is lost
  Send(stream, 11, 16, true);
  std::vector<hw::GyroSample> out(64);
  ASSERT_EQ(stream.Pop(out), 16u);  // up to the report at 15
  for (std::size_t i = 0; i < 16; ++i) {
    EXPECT_NEAR(std::remainder(out[i].reference_phase_rad - Chi(i), 2 * kPi), 0.0, 1e-8) << i;
    EXPECT_NEAR(out[i].y[0], Locked1(i).real(), 4e-7) << i;
  }
}

TEST(ReferencePhaseStreamTest, ElectronicsWithoutReportsAreUnchanged) {
  SampleStreamDecoder stream(1024);
  stream.Start(FrameFormat::kClassic, 1000);
  Send(stream, 0, 50, false);
  std::vector<hw::GyroSample> out(64);
  ASSERT_EQ(stream.Pop(out), 50u);
  for (std::size_t i = 0; i < 50; ++i) {
    EXPECT_TRUE(std::isnan(out[i].reference_phase_rad));
    const std::complex<double> sent = std::polar(1.0, -Chi(i)) * Locked1(i);
    EXPECT_EQ(out[i].y[0], DequantiseY(QuantiseY(sent.real()))) << i;
  }
  EXPECT_EQ(stream.counters().reference_phases_missing, 0u);
}

TEST(ReferencePhaseStreamTest, AReportThatNeverComesHoldsBoundedAndIsCounted) {
  SampleStreamDecoder stream(1024);
  stream.Start(FrameFormat::kClassic, 1000);
  Send(stream, 0, 11, true);    // reports at 0, 5, 10
  Send(stream, 11, 60, false);  // then none
  std::vector<hw::GyroSample> out(64);
  // 0..10 turned; 11..39 given up (each 20 samples older than the newest, 59); 40..59 wait.
  const std::size_t n = stream.Pop(out);
  ASSERT_EQ(n, 40u);
  EXPECT_FALSE(std::isnan(out[10].reference_phase_rad));
  EXPECT_TRUE(std::isnan(out[11].reference_phase_rad));
  EXPECT_TRUE(std::isnan(out[39].reference_phase_rad));
  EXPECT_EQ(stream.counters().reference_phases_missing, 29u);
  EXPECT_EQ(stream.Buffered(), 20u);
  static_assert(SampleStreamDecoder::kReferenceHoldSamples == 20);
}

TEST(ReferencePhaseStreamTest, FdBlocksAreTurnedToo) {
  SampleStreamDecoder stream(1024);
  stream.Start(FrameFormat::kFd, 5000);
  for (std::uint64_t first = 0; first < 100; first += kSamplesPerFdFrame) {
    SendReport(stream, first);
    SampleFdBlock block{static_cast<std::uint16_t>(first), kSamplesPerFdFrame, {}};
    for (std::size_t s = 0; s < kSamplesPerFdFrame; ++s) {
      const std::uint64_t k = first + s;
      const std::complex<double> turn = std::polar(1.0, -Chi(k));
      const std::complex<double> u1 = turn * Locked1(k), u2 = turn * Locked2(k);
      block.y_raw[s] = {QuantiseY(u1.real()), QuantiseY(u1.imag()), QuantiseY(u2.real()),
                        QuantiseY(u2.imag())};
    }
    stream.OnSampleFd(block, 0);
  }
  std::vector<hw::GyroSample> out(128);
  const std::size_t n = stream.Pop(out);
  ASSERT_EQ(n, 96u);  // up to the last report, 95
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_NEAR(out[i].y[2], Locked2(i).real(), 4e-7) << i;
    EXPECT_NEAR(out[i].y[3], Locked2(i).imag(), 4e-7) << i;
  }
}

}  // namespace
}  // namespace hrgbench::drivers::gyro_can
