#pragma once
// The CanBus conformance tests (see can_bus_conformance.hpp for how to instantiate them). Include
// in exactly one translation unit per test binary: it defines tests and replaces operator new.

#include <chrono>
#include <vector>

#include "allocation_counter.hpp"
#include "can_bus_conformance.hpp"

namespace hrgbench::testing {

using hw::CanFilter;
using hw::CanFrame;
using hw::CanStatus;

TEST_P(CanBusConformanceTest, ClassicFramesArriveByteExactInBothDirections) {
  for (std::uint8_t length = 0; length <= 8; ++length) {
    ExpectRoundTrip(a(), b(), Frame(0x100u + length, length, false, length));
    ExpectRoundTrip(b(), a(), Frame(0x7FFu - length, length, false, length));
  }
}

TEST_P(CanFdConformanceTest, FdFramesArriveByteExactWithAndWithoutBitRateSwitch) {
  constexpr std::uint8_t kLengths[] = {0, 1, 7, 8, 12, 16, 20, 24, 32, 48, 64};
  for (std::uint8_t length : kLengths) {
    ExpectRoundTrip(a(), b(), FdFrame(0x200, length, false, length));
    ExpectRoundTrip(a(), b(), FdFrame(0x201, length, true, length));
  }
  CanFrame extended = FdFrame(0x1ABCDEF0, 64, true, 9);
  extended.extended = true;
  ExpectRoundTrip(b(), a(), extended);
}

TEST_P(CanBusConformanceTest, ExtendedAndStandardIdsKeepTheirFormat) {
  for (std::uint32_t id : {0x0u, 0x1u, 0x7FFu, 0x800u, 0x12345678u, 0x1FFFFFFFu}) {
    ExpectRoundTrip(a(), b(), Frame(id, 4, true, 3));
  }
  for (std::uint32_t id : {0x0u, 0x7FFu}) ExpectRoundTrip(a(), b(), Frame(id, 2, false));
}

TEST_P(CanBusConformanceTest, RemoteFramesKeepIdAndRequestedLength) {
  CanFrame standard = Frame(0x321, 0);
  standard.remote = true;
  ExpectRoundTrip(a(), b(), standard);
  CanFrame extended = Frame(0x1234567, 0, true);
  extended.remote = true;
  extended.length = 8;  // a remote frame's DLC is the length it requests; it carries no data
  ExpectRoundTrip(a(), b(), extended);
}

// Sends `count` frames carrying a 32-bit sequence number; batches keep any receive buffer from
// overflowing (a kernel socket holds a few hundred frames) without relying on timing.
void ExpectOrdered(hw::CanBus& tx, hw::CanBus& rx, int count, bool fd) {
  constexpr int kBatch = 64;
  std::uint32_t next_expected = 0;
  for (int sent = 0; sent < count;) {
    for (int i = 0; i < kBatch && sent < count; ++i, ++sent) {
      CanFrame frame;
      frame.id = 0x100u + static_cast<std::uint32_t>(sent % 0x600);
      frame.fd = fd;
      frame.bit_rate_switch = fd;  // as FD is used in practice: payload at the data bit rate
      frame.length = fd ? 64 : 8;
      for (std::uint8_t k = 0; k < 4; ++k) {
        frame.data[k] = static_cast<std::uint8_t>(static_cast<std::uint32_t>(sent) >> (8 * k));
      }
      frame.data[frame.length - 1] = static_cast<std::uint8_t>(sent);
      ASSERT_EQ(tx.Send(frame, 2'000'000'000), CanStatus::kOk) << "frame " << sent;
    }
    while (next_expected < static_cast<std::uint32_t>(sent)) {
      CanFrame frame;
      hw::ReceiveInfo info;
      ASSERT_EQ(rx.Receive(&frame, 2'000'000'000, &info), CanStatus::kOk)
          << "waiting for frame " << next_expected;
      const std::uint32_t sequence = frame.data[0] | frame.data[1] << 8 | frame.data[2] << 16 |
                                     static_cast<std::uint32_t>(frame.data[3]) << 24;
      ASSERT_EQ(sequence, next_expected) << hw::CanFrameToString(frame);
      ASSERT_EQ(frame.id, 0x100u + next_expected % 0x600);
      ASSERT_EQ(info.dropped_frames, 0u);
      ++next_expected;
    }
  }
}

TEST_P(CanBusConformanceTest, TenThousandClassicFramesArriveInOrder) {
  ExpectOrdered(a(), b(), 10'000, false);
}

TEST_P(CanFdConformanceTest, TenThousandFdFramesArriveInOrder) {
  ExpectOrdered(a(), b(), 10'000, true);
}

TEST_P(CanBusConformanceTest, IdMaskFilterPassesOnlyMatchingStandardFrames) {
  const CanFilter filter{0x120, 0x7F0, false};
  ASSERT_EQ(b().SetFilters({&filter, 1}), CanStatus::kOk);
  CanFrame remote = Frame(0x121, 1);
  remote.remote = true;
  const std::vector<CanFrame> sent = {Frame(0x133, 1), Frame(0x123, 1), Frame(0x123, 1, true),
                                      Frame(0x020, 1), remote,          Frame(0x12F, 2)};
  for (const CanFrame& frame : sent) ASSERT_EQ(a().Send(frame, kReceiveTimeoutNs), CanStatus::kOk);
  for (const CanFrame& expected : {sent[1], sent[4], sent[5]}) {
    CanFrame received;
    ASSERT_EQ(b().Receive(&received, kReceiveTimeoutNs, nullptr), CanStatus::kOk);
    EXPECT_TRUE(SameFrame(expected, received));
  }
  CanFrame extra;
  EXPECT_EQ(b().Receive(&extra, 0, nullptr), CanStatus::kTimeout) << hw::CanFrameToString(extra);
}

TEST_P(CanBusConformanceTest, FiltersSeparateExtendedFromStandardAndAreOred) {
  const CanFilter filters[] = {{0x18FF0000, 0x1FFF0000, true}, {0x7FF, 0x7FF, false}};
  ASSERT_EQ(b().SetFilters(filters), CanStatus::kOk);
  const std::vector<CanFrame> sent = {Frame(0x18FE0000, 1, true), Frame(0x18FF1234, 1, true),
                                      Frame(0x7FF, 1, true),      Frame(0x7FF, 3, false),
                                      Frame(0x000, 1, false),     Frame(0x18FFFFFF, 5, true)};
  for (const CanFrame& frame : sent) ASSERT_EQ(a().Send(frame, kReceiveTimeoutNs), CanStatus::kOk);
  for (const CanFrame& expected : {sent[1], sent[3], sent[5]}) {
    CanFrame received;
    ASSERT_EQ(b().Receive(&received, kReceiveTimeoutNs, nullptr), CanStatus::kOk);
    EXPECT_TRUE(SameFrame(expected, received));
  }
  CanFrame extra;
  EXPECT_EQ(b().Receive(&extra, 0, nullptr), CanStatus::kTimeout) << hw::CanFrameToString(extra);
}

TEST_P(CanBusConformanceTest, TooManyFiltersAreRefused) {
  std::vector<CanFilter> filters(hw::kMaxCanFilters + 1, CanFilter{0x1, 0x7FF, false});
  EXPECT_EQ(b().SetFilters(filters), CanStatus::kInvalidArgument);
  ExpectRoundTrip(a(), b(), Frame(0x555, 1));  // previous (accept-all) filters still apply
}

TEST_P(CanBusConformanceTest, ReceiveTimeoutIsAStatusWithinTolerance) {
  constexpr std::int64_t kTimeoutNs = 50'000'000;
  CanFrame frame;
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(b().Receive(&frame, kTimeoutNs, nullptr), CanStatus::kTimeout);
  const std::int64_t elapsed_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start)
          .count();
  EXPECT_GE(elapsed_ns, kTimeoutNs - 1'000'000);      // never early (1 ms for clock granularity)
  EXPECT_LE(elapsed_ns, kTimeoutNs + 1'000'000'000);  // generous: loaded CI, emulated guests
  EXPECT_EQ(b().Receive(&frame, 0, nullptr), CanStatus::kTimeout);
  EXPECT_EQ(b().Receive(nullptr, 0, nullptr), CanStatus::kInvalidArgument);
}

TEST_P(CanBusConformanceTest, StatisticsCountEveryOutcome) {
  const hw::CanBusStatistics a0 = a().Statistics();
  const hw::CanBusStatistics b0 = b().Statistics();
  for (std::uint8_t i = 0; i < 3; ++i) ExpectRoundTrip(a(), b(), Frame(0x10u + i, i));
  CanFrame bad = Frame(0x800, 1);  // 12-bit id in a standard frame
  EXPECT_EQ(a().Send(bad, 0), CanStatus::kInvalidFrame);
  bad = Frame(0x10, 8);
  bad.length = 9;
  EXPECT_EQ(a().Send(bad, 0), CanStatus::kInvalidFrame);
  CanFrame frame;
  EXPECT_EQ(b().Receive(&frame, 1'000'000, nullptr), CanStatus::kTimeout);
  const hw::CanBusStatistics a1 = a().Statistics();
  const hw::CanBusStatistics b1 = b().Statistics();
  EXPECT_EQ(a1.frames_sent - a0.frames_sent, 3u);
  EXPECT_EQ(a1.invalid_frames - a0.invalid_frames, 2u);
  EXPECT_EQ(b1.frames_received - b0.frames_received, 3u);
  EXPECT_EQ(b1.timeouts - b0.timeouts, 1u);
  EXPECT_EQ(b1.dropped_frames - b0.dropped_frames, 0u);
  EXPECT_EQ(a1.send_errors - a0.send_errors, 0u);
}

TEST_P(CanBusConformanceTest, InvalidFramesAreRefusedAndNotSent) {
  CanFrame fd_remote = FdFrame(0x10, 0, false);
  fd_remote.remote = true;
  CanFrame fd_bad_length = FdFrame(0x10, 13, false);
  CanFrame classic_brs = Frame(0x10, 1);
  classic_brs.bit_rate_switch = true;
  CanFrame error_frame = Frame(0x4, 8);
  error_frame.error = true;
  CanFrame extended_too_big = Frame(0x20000000, 1, true);
  for (const CanFrame& frame :
       {fd_remote, fd_bad_length, classic_brs, error_frame, extended_too_big}) {
    EXPECT_EQ(a().Send(frame, 0), CanStatus::kInvalidFrame) << hw::CanFrameToString(frame);
  }
  if (!a().SupportsFd()) {
    EXPECT_EQ(a().Send(FdFrame(0x10, 8, false), 0), CanStatus::kInvalidFrame);
  }
  ExpectRoundTrip(a(), b(), Frame(0x7AB, 1));  // the first frame through is the valid one
}

TEST_P(CanBusConformanceTest, SenderDoesNotReceiveItsOwnFrames) {
  ExpectRoundTrip(a(), b(), Frame(0x42, 1));
  CanFrame frame;
  EXPECT_EQ(a().Receive(&frame, 0, nullptr), CanStatus::kTimeout) << hw::CanFrameToString(frame);
}

TEST_P(CanBusConformanceTest, TimestampsAreStampedAndMonotonicPerSource) {
  hw::ReceiveInfo previous;
  for (std::uint8_t i = 0; i < 50; ++i) {
    ASSERT_EQ(a().Send(Frame(0x60, 1, false, i), kReceiveTimeoutNs), CanStatus::kOk);
    CanFrame frame;
    hw::ReceiveInfo info;
    ASSERT_EQ(b().Receive(&frame, kReceiveTimeoutNs, &info), CanStatus::kOk);
    EXPECT_NE(info.timestamp_source, hw::TimestampSource::kNone);
    if (i > 0 && info.timestamp_source == previous.timestamp_source) {
      EXPECT_GE(info.timestamp_ns, previous.timestamp_ns);
    }
    previous = info;
  }
}

TEST_P(CanBusConformanceTest, StateIsNotBusOffOnAHealthyBus) {
  EXPECT_NE(a().State(), hw::CanBusState::kBusOff);
  EXPECT_NE(b().State(), hw::CanBusState::kBusOff);
}

TEST_P(CanBusConformanceTest, SendAndReceiveDoNotAllocate) {
  ExpectRoundTrip(a(), b(), Frame(0x70, 8));  // warm-up: lazy first-use setup is allowed
  CanFrame frame = Frame(0x71, 8);
  CanFrame received;
  hw::ReceiveInfo info;
  int round_trips = 0;
  const AllocationScope scope;
  for (; round_trips < 100; ++round_trips) {
    if (a().Send(frame, kReceiveTimeoutNs) != CanStatus::kOk) break;
    if (b().Receive(&received, kReceiveTimeoutNs, &info) != CanStatus::kOk) break;
  }
  const std::int64_t allocations = scope.Count();
  EXPECT_EQ(round_trips, 100);
  EXPECT_EQ(allocations, 0);
}

}  // namespace hrgbench::testing
