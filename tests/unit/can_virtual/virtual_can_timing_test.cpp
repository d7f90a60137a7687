// Bit-rate-limited timing on a ManualClock: no sleeps, time moves only when the test says so (or
// when Receive waits, with an auto-advancing clock).

#include <gtest/gtest.h>

#include <vector>

#include "can_virtual/virtual_can_bus.hpp"

namespace hrgbench::drivers::can_virtual {
namespace {

using hw::CanFrame;
using hw::CanStatus;

CanFrame EightBytes(std::uint8_t tag) {
  CanFrame frame;
  frame.id = 0x123;
  frame.length = 8;
  frame.data[0] = tag;
  return frame;
}

struct TimedBus {
  explicit TimedBus(bool auto_advance) : clock(0, auto_advance) {
    VirtualCanBusOptions options;
    options.nominal_bit_rate_bps = 1'000'000;
    options.data_bit_rate_bps = 8'000'000;
    options.clock = &clock;
    bus = std::move(*VirtualCanBus::Create(options));
    a = bus->CreateEndpoint();
    b = bus->CreateEndpoint();
  }
  hw::ManualClock clock;
  std::unique_ptr<VirtualCanBus> bus;
  std::unique_ptr<VirtualCanEndpoint> a, b;
};

TEST(VirtualCanTiming, AFrameIsVisibleOnlyAfterItsEndOfFrame) {
  TimedBus t(/*auto_advance=*/false);
  ASSERT_EQ(t.a->Send(EightBytes(1), 0), CanStatus::kOk);
  EXPECT_EQ(t.bus->BusIdleAtNs(), 111'000);  // 111 bits at 1 Mbit/s
  CanFrame frame;
  hw::ReceiveInfo info;
  t.clock.Set(110'999);
  EXPECT_EQ(t.b->Receive(&frame, 0, &info), CanStatus::kTimeout);
  t.clock.Set(111'000);
  ASSERT_EQ(t.b->Receive(&frame, 0, &info), CanStatus::kOk);
  EXPECT_EQ(info.timestamp_ns, 111'000);
  EXPECT_EQ(info.timestamp_source, hw::TimestampSource::kHardware);
}

TEST(VirtualCanTiming, BackToBackFramesQueueOnTheBusAndReceiveWaitsInClockTime) {
  TimedBus t(/*auto_advance=*/true);
  for (std::uint8_t i = 0; i < 3; ++i) ASSERT_EQ(t.a->Send(EightBytes(i), 0), CanStatus::kOk);
  EXPECT_EQ(t.clock.NowNs(), 0);  // Send does not wait for the bus
  for (std::int64_t i = 1; i <= 3; ++i) {
    CanFrame frame;
    hw::ReceiveInfo info;
    ASSERT_EQ(t.b->Receive(&frame, 1'000'000'000, &info), CanStatus::kOk);
    EXPECT_EQ(frame.data[0], i - 1);
    EXPECT_EQ(info.timestamp_ns, i * 111'000);
    EXPECT_EQ(t.clock.NowNs(), i * 111'000);  // Receive slept exactly until the end of frame
  }
}

// A node sharing a busy bus: its transmit queue of 3 fills while another node's 10 frames hold
// the bus, the 4th Send is refused (the frame lost at the source, counted), and a frame leaving
// the queue (its end of frame passing) makes room again.
TEST(VirtualCanTiming, AFullTransmitQueueRefusesTheFrame) {
  TimedBus t(/*auto_advance=*/false);
  auto c = t.bus->CreateEndpoint(
      {.receive_own_frames = false, .queue_capacity = 0, .transmit_queue_frames = 3});
  for (std::uint8_t i = 0; i < 10; ++i) ASSERT_EQ(t.a->Send(EightBytes(i), 0), CanStatus::kOk);
  for (std::uint8_t i = 0; i < 3; ++i) ASSERT_EQ(c->Send(EightBytes(100 + i), 0), CanStatus::kOk);
  EXPECT_EQ(c->Send(EightBytes(103), 0), CanStatus::kBufferFull);
  EXPECT_EQ(c->Statistics().buffer_full, 1u);
  EXPECT_EQ(c->Statistics().frames_sent, 3u);
  EXPECT_EQ(t.bus->BusIdleAtNs(), 13 * 111'000);  // the refused frame never took the bus
  t.clock.Set(11 * 111'000 - 1);                  // c's first frame still on the wire
  EXPECT_EQ(c->Send(EightBytes(104), 0), CanStatus::kBufferFull);
  t.clock.Set(11 * 111'000);  // its end of frame: out of the queue
  EXPECT_EQ(c->Send(EightBytes(105), 0), CanStatus::kOk);
  // b heard a's 10, then c's 100, 101, 102, 105 and nothing of what c could not send.
  t.clock.Set(1'000'000'000);
  std::vector<int> heard;
  CanFrame frame;
  while (t.b->Receive(&frame, 0, nullptr) == CanStatus::kOk) heard.push_back(frame.data[0]);
  ASSERT_EQ(heard.size(), 14u);
  EXPECT_EQ(std::vector<int>(heard.begin() + 10, heard.end()),
            (std::vector<int>{100, 101, 102, 105}));
}

TEST(VirtualCanTiming, AnIdleBusStartsTheNextFrameAtItsSend) {
  TimedBus t(/*auto_advance=*/true);
  ASSERT_EQ(t.a->Send(EightBytes(0), 0), CanStatus::kOk);
  t.clock.Set(1'000'000);
  ASSERT_EQ(t.b->Send(EightBytes(1), 0), CanStatus::kOk);
  EXPECT_EQ(t.bus->BusIdleAtNs(), 1'111'000);
  CanFrame frame;
  hw::ReceiveInfo info;
  ASSERT_EQ(t.a->Receive(&frame, 1'000'000, &info), CanStatus::kOk);
  EXPECT_EQ(info.timestamp_ns, 1'111'000);
  EXPECT_EQ(t.clock.NowNs(), 1'111'000);
}

TEST(VirtualCanTiming, ReceiveTimeoutIsExactInClockTime) {
  TimedBus t(/*auto_advance=*/true);
  CanFrame frame;
  EXPECT_EQ(t.b->Receive(&frame, 5'000'000, nullptr), CanStatus::kTimeout);
  EXPECT_EQ(t.clock.NowNs(), 5'000'000);
  // A frame still on the wire when the timeout expires is not returned early.
  ASSERT_EQ(t.a->Send(EightBytes(0), 0), CanStatus::kOk);
  EXPECT_EQ(t.b->Receive(&frame, 100'000, nullptr), CanStatus::kTimeout);
  EXPECT_EQ(t.clock.NowNs(), 5'100'000);
  EXPECT_EQ(t.b->Statistics().timeouts, 2u);
}

TEST(VirtualCanTiming, OneSecondAt1MbitCarries9009EightByteFrames) {
  TimedBus t(/*auto_advance=*/false);
  auto rx = t.bus->CreateEndpoint({.queue_capacity = 10'000});
  // Saturate the bus, then count what has finished within one second of bus time.
  for (int i = 0; i < 10'000; ++i) ASSERT_EQ(t.a->Send(EightBytes(0), 0), CanStatus::kOk);
  t.clock.Set(1'000'000'000);
  int delivered = 0;
  CanFrame frame;
  while (rx->Receive(&frame, 0, nullptr) == CanStatus::kOk) ++delivered;
  // 1 s / 111 µs = 9009 (no stuff bits; with worst-case stuffing a real bus carries ~7 800).
  EXPECT_EQ(delivered, 9009);
  EXPECT_EQ(rx->Statistics().dropped_frames, 0u);
}

TEST(VirtualCanTiming, FdWithBitRateSwitchSpendsThePayloadAtTheDataRate) {
  TimedBus t(/*auto_advance=*/false);
  CanFrame frame;
  frame.id = 0x10;
  frame.fd = true;
  frame.bit_rate_switch = true;
  frame.length = 64;
  ASSERT_EQ(t.a->Send(frame, 0), CanStatus::kOk);
  EXPECT_EQ(t.bus->BusIdleAtNs(), 29'000 + 67'875);  // see can_bit_timing_test.cpp
}

}  // namespace
}  // namespace hrgbench::drivers::can_virtual
