// The virtual bus beyond the CanBus contract: fan-out, loopback, fault injection, bus-off, queue
// overflow, concurrent senders.

#include "can_virtual/virtual_can_bus.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <bit>
#include <set>
#include <thread>
#include <vector>

#include "can_frame_assertions.hpp"

namespace hrgbench::drivers::can_virtual {
namespace {

using hw::CanBusState;
using hw::CanFrame;
using hw::CanStatus;

CanFrame Sequenced(std::uint32_t sequence, std::uint32_t id = 0x123) {
  CanFrame frame;
  frame.id = id;
  frame.length = 8;
  for (std::uint8_t k = 0; k < 4; ++k) frame.data[k] = static_cast<std::uint8_t>(sequence >> 8 * k);
  frame.data[7] = 0xA5;
  return frame;
}

std::uint32_t SequenceOf(const CanFrame& frame) {
  return frame.data[0] | frame.data[1] << 8 | frame.data[2] << 16 |
         static_cast<std::uint32_t>(frame.data[3]) << 24;
}

std::unique_ptr<VirtualCanBus> MakeBus(const VirtualCanBusOptions& options = {}) {
  auto bus = VirtualCanBus::Create(options);
  EXPECT_TRUE(bus.has_value()) << (bus ? "" : bus.error());
  return bus ? std::move(*bus) : nullptr;
}

TEST(VirtualCanBus, InvalidOptionsAreRefusedWithTheReason) {
  VirtualCanBusOptions options;
  options.queue_capacity = 0;
  auto bus = VirtualCanBus::Create(options);
  ASSERT_FALSE(bus.has_value());
  EXPECT_NE(bus.error().find("queue_capacity"), std::string::npos) << bus.error();
  options = {};
  options.drop_probability = 1.5;
  EXPECT_FALSE(VirtualCanBus::Create(options).has_value());
}

TEST(VirtualCanBus, EveryOtherEndpointReceivesAndLoopbackIsOptIn) {
  auto bus = MakeBus();
  auto a = bus->CreateEndpoint();
  auto b = bus->CreateEndpoint();
  auto own = bus->CreateEndpoint({.receive_own_frames = true});
  ASSERT_EQ(a->Send(Sequenced(1), 0), CanStatus::kOk);
  ASSERT_EQ(own->Send(Sequenced(2), 0), CanStatus::kOk);
  CanFrame frame;
  ASSERT_EQ(b->Receive(&frame, 0, nullptr), CanStatus::kOk);
  EXPECT_EQ(SequenceOf(frame), 1u);
  ASSERT_EQ(b->Receive(&frame, 0, nullptr), CanStatus::kOk);
  EXPECT_EQ(SequenceOf(frame), 2u);
  ASSERT_EQ(a->Receive(&frame, 0, nullptr), CanStatus::kOk);
  EXPECT_EQ(SequenceOf(frame), 2u);  // a does not see its own frame 1
  ASSERT_EQ(own->Receive(&frame, 0, nullptr), CanStatus::kOk);
  EXPECT_EQ(SequenceOf(frame), 1u);
  ASSERT_EQ(own->Receive(&frame, 0, nullptr), CanStatus::kOk);
  EXPECT_EQ(SequenceOf(frame), 2u);  // its own, with receive_own_frames
  EXPECT_EQ(bus->Statistics().frames_on_bus, 2u);
}

TEST(VirtualCanBus, EmptyFilterListPassesNothing) {
  auto bus = MakeBus();
  auto a = bus->CreateEndpoint();
  auto deaf = bus->CreateEndpoint();
  auto all = bus->CreateEndpoint();
  ASSERT_EQ(deaf->SetFilters({}), CanStatus::kOk);
  ASSERT_EQ(a->Send(Sequenced(7), 0), CanStatus::kOk);
  CanFrame frame;
  ASSERT_EQ(all->Receive(&frame, 0, nullptr), CanStatus::kOk);  // delivery done for everyone
  EXPECT_EQ(deaf->Receive(&frame, 0, nullptr), CanStatus::kTimeout);
}

TEST(VirtualCanBus, DropNextLosesExactlyThoseFramesForEveryReceiver) {
  auto bus = MakeBus();
  auto a = bus->CreateEndpoint();
  auto b = bus->CreateEndpoint();
  auto c = bus->CreateEndpoint();
  bus->DropNext(2);
  for (std::uint32_t i = 0; i < 5; ++i) ASSERT_EQ(a->Send(Sequenced(i), 0), CanStatus::kOk);
  for (auto* rx : {b.get(), c.get()}) {
    for (std::uint32_t expected : {2u, 3u, 4u}) {
      CanFrame frame;
      hw::ReceiveInfo info;
      ASSERT_EQ(rx->Receive(&frame, 0, &info), CanStatus::kOk);
      EXPECT_EQ(SequenceOf(frame), expected);
      EXPECT_EQ(info.dropped_frames, 0u);  // a loss on the wire is invisible to the receiver
    }
    CanFrame frame;
    EXPECT_EQ(rx->Receive(&frame, 0, nullptr), CanStatus::kTimeout);
  }
  EXPECT_EQ(bus->Statistics().injected_drops, 2u);
  EXPECT_EQ(a->Statistics().frames_sent, 5u);
}

TEST(VirtualCanBus, CorruptNextFlipsExactlyOneDataBitOfFramesWithData) {
  auto bus = MakeBus();
  auto a = bus->CreateEndpoint();
  auto b = bus->CreateEndpoint();
  bus->CorruptNext(1);
  CanFrame empty;
  empty.id = 0x10;
  ASSERT_EQ(a->Send(empty, 0), CanStatus::kOk);  // no data bit to flip: passes unharmed
  const CanFrame sent = Sequenced(0xDEADBEEF);
  ASSERT_EQ(a->Send(sent, 0), CanStatus::kOk);
  ASSERT_EQ(a->Send(sent, 0), CanStatus::kOk);
  CanFrame frame;
  ASSERT_EQ(b->Receive(&frame, 0, nullptr), CanStatus::kOk);
  EXPECT_TRUE(testing::SameFrame(empty, frame));
  ASSERT_EQ(b->Receive(&frame, 0, nullptr), CanStatus::kOk);
  int flipped_bits = 0;
  for (std::size_t i = 0; i < 8; ++i) {
    flipped_bits += std::popcount(static_cast<unsigned>(frame.data[i] ^ sent.data[i]));
  }
  EXPECT_EQ(flipped_bits, 1) << hw::CanFrameToString(sent) << " -> " << hw::CanFrameToString(frame);
  ASSERT_EQ(b->Receive(&frame, 0, nullptr), CanStatus::kOk);
  EXPECT_TRUE(testing::SameFrame(sent, frame));
  EXPECT_EQ(bus->Statistics().injected_corruptions, 1u);
}

std::vector<std::uint32_t> SurvivorsOfRandomDrops(std::uint64_t seed, std::uint64_t* drops) {
  VirtualCanBusOptions options;
  options.drop_probability = 0.25;
  options.seed = seed;
  options.queue_capacity = 4096;
  auto bus = MakeBus(options);
  auto a = bus->CreateEndpoint();
  auto b = bus->CreateEndpoint();
  for (std::uint32_t i = 0; i < 2000; ++i) EXPECT_EQ(a->Send(Sequenced(i), 0), CanStatus::kOk);
  std::vector<std::uint32_t> survivors;
  CanFrame frame;
  while (b->Receive(&frame, 0, nullptr) == CanStatus::kOk) survivors.push_back(SequenceOf(frame));
  *drops = bus->Statistics().injected_drops;
  return survivors;
}

TEST(VirtualCanBus, RandomDropsAreReproducibleFromTheSeed) {
  std::uint64_t drops = 0;
  const auto first = SurvivorsOfRandomDrops(42, &drops);
  EXPECT_EQ(first.size() + drops, 2000u);
  EXPECT_GT(drops, 400u);  // expected 500; binomial σ ≈ 19
  EXPECT_LT(drops, 600u);
  std::uint64_t drops_again = 0;
  EXPECT_EQ(SurvivorsOfRandomDrops(42, &drops_again), first);
  EXPECT_NE(SurvivorsOfRandomDrops(43, &drops_again), first);
}

TEST(VirtualCanBus, BusOffStopsSendingAndReceivingUntilRecovery) {
  auto bus = MakeBus();
  auto a = bus->CreateEndpoint();
  auto b = bus->CreateEndpoint();
  a->InjectState(CanBusState::kBusOff);
  EXPECT_EQ(a->State(), CanBusState::kBusOff);
  EXPECT_EQ(a->Send(Sequenced(1), 0), CanStatus::kBusOff);
  ASSERT_EQ(b->Send(Sequenced(2), 0), CanStatus::kOk);  // not received by the bus-off node
  CanFrame frame;
  EXPECT_EQ(a->Receive(&frame, 1'000'000, nullptr), CanStatus::kBusOff);
  EXPECT_EQ(b->Receive(&frame, 0, nullptr), CanStatus::kTimeout);
  EXPECT_EQ(a->Statistics().send_errors, 1u);
  EXPECT_EQ(a->Statistics().error_frames, 1u);

  a->InjectState(CanBusState::kErrorActive);
  ASSERT_EQ(a->Send(Sequenced(3), 0), CanStatus::kOk);
  ASSERT_EQ(b->Receive(&frame, 0, nullptr), CanStatus::kOk);
  EXPECT_EQ(SequenceOf(frame), 3u);

  bus->SetBusOff(true);
  EXPECT_EQ(a->State(), CanBusState::kBusOff);
  EXPECT_EQ(b->Send(Sequenced(4), 0), CanStatus::kBusOff);
  bus->SetBusOff(false);
  EXPECT_EQ(b->State(), CanBusState::kErrorActive);
}

TEST(VirtualCanBus, FullQueueDropsTheOldestAndReportsTheGap) {
  auto bus = MakeBus();
  auto a = bus->CreateEndpoint();
  auto b = bus->CreateEndpoint({.queue_capacity = 4});
  for (std::uint32_t i = 0; i < 10; ++i) ASSERT_EQ(a->Send(Sequenced(i), 0), CanStatus::kOk);
  CanFrame frame;
  hw::ReceiveInfo info;
  ASSERT_EQ(b->Receive(&frame, 0, &info), CanStatus::kOk);
  EXPECT_EQ(SequenceOf(frame), 6u);
  EXPECT_EQ(info.dropped_frames, 6u);
  ASSERT_EQ(b->Receive(&frame, 0, &info), CanStatus::kOk);
  EXPECT_EQ(SequenceOf(frame), 7u);
  EXPECT_EQ(info.dropped_frames, 0u);
  EXPECT_EQ(b->Statistics().dropped_frames, 6u);
}

// Two sender threads, one receiver with a small queue: each sender's frames arrive in order, and
// every gap in a sender's sequence is a counted drop.
TEST(VirtualCanBus, ConcurrentSendersKeepOrderAndEveryLossIsCounted) {
  constexpr std::uint32_t kPerSender = 20'000;
  auto bus = MakeBus({.queue_capacity = 64});
  auto s0 = bus->CreateEndpoint();
  auto s1 = bus->CreateEndpoint();
  auto rx = bus->CreateEndpoint();
  std::atomic<int> senders_done{0};
  auto send = [&senders_done](VirtualCanEndpoint* tx, std::uint32_t id) {
    for (std::uint32_t i = 0; i < kPerSender; ++i) {
      EXPECT_EQ(tx->Send(Sequenced(i, id), 0), CanStatus::kOk);
    }
    senders_done.fetch_add(1);
  };
  std::jthread t0(send, s0.get(), 0x100);
  std::jthread t1(send, s1.get(), 0x101);
  std::int64_t next[2] = {0, 0};
  std::uint64_t received = 0, gaps = 0;
  bool out_of_order = false;
  const auto take = [&](const CanFrame& frame) {
    const std::size_t k = frame.id - 0x100;
    const std::int64_t sequence = SequenceOf(frame);
    out_of_order = out_of_order || sequence < next[k];
    gaps += static_cast<std::uint64_t>(sequence - next[k]);
    next[k] = sequence + 1;
    ++received;
  };
  CanFrame frame;
  for (;;) {
    const CanStatus status = rx->Receive(&frame, 1'000'000, nullptr);
    if (status == CanStatus::kOk) {
      take(frame);
    } else if (senders_done.load() == 2) {
      break;  // every Send has returned, so every frame is queued: drain below
    }
  }
  while (rx->Receive(&frame, 0, nullptr) == CanStatus::kOk) take(frame);
  EXPECT_FALSE(out_of_order);
  gaps += static_cast<std::uint64_t>((kPerSender - next[0]) + (kPerSender - next[1]));
  EXPECT_EQ(received + gaps, 2u * kPerSender);
  EXPECT_EQ(rx->Statistics().dropped_frames, gaps);
  EXPECT_EQ(rx->Statistics().frames_received, received);
}

}  // namespace
}  // namespace hrgbench::drivers::can_virtual
