// What only a real kernel can show: the SO_RXQ_OVFL drop counter, FD negotiation from the MTU,
// own-frame reception. Skipped (with the reason) where AF_CAN or the interface is missing.

#include <gtest/gtest.h>

#include "socketcan/socket_can_bus.hpp"
#include "vcan_name.hpp"

namespace hrgbench::drivers::socketcan {
namespace {

using hw::CanFrame;
using hw::CanStatus;

std::unique_ptr<SocketCanBus> OpenOrNull(const SocketCanOptions& options, std::string* why) {
  auto bus = SocketCanBus::Open(testing::VcanName(), options);
  if (!bus) {
    *why = bus.error();
    return nullptr;
  }
  return std::move(*bus);
}

#define OPEN_OR_SKIP(var, options)                                                \
  std::string var##_why;                                                          \
  auto var = OpenOrNull(options, &var##_why);                                     \
  if (!var && testing::VcanRequired()) GTEST_FAIL() << "required: " << var##_why; \
  if (!var) GTEST_SKIP() << "SocketCAN unavailable: " << var##_why

TEST(SocketCanKernel, SocketQueueOverflowIsCountedAndReportedWithTheNextFrame) {
  SocketCanOptions small;
  small.receive_buffer_bytes = 4096;  // the kernel's minimum: a handful of frames
  OPEN_OR_SKIP(rx, small);
  OPEN_OR_SKIP(tx, SocketCanOptions{});
  constexpr int kSent = 500;
  CanFrame frame;
  frame.id = 0x321;
  frame.length = 8;
  for (int i = 0; i < kSent; ++i) {
    frame.data[0] = static_cast<std::uint8_t>(i);
    ASSERT_EQ(tx->Send(frame, 1'000'000'000), CanStatus::kOk);
  }
  // Drain until quiet (the kernel may still be delivering from its backlog), then send a marker:
  // the kernel stamps each queued frame with the socket's drop count, so the marker reports the
  // gap.
  std::uint64_t received = 0, reported = 0;
  hw::ReceiveInfo info;
  while (rx->Receive(&frame, 200'000'000, &info) == CanStatus::kOk) {
    ++received;
    reported += info.dropped_frames;
  }
  EXPECT_GT(received, 0u);
  EXPECT_LT(received, static_cast<std::uint64_t>(kSent));
  frame.data[0] = 0xEE;
  frame.id = 0x322;
  ASSERT_EQ(tx->Send(frame, 1'000'000'000), CanStatus::kOk);
  ASSERT_EQ(rx->Receive(&frame, 1'000'000'000, &info), CanStatus::kOk);
  EXPECT_EQ(frame.id, 0x322u);
  reported += info.dropped_frames;
  EXPECT_EQ(received + reported, static_cast<std::uint64_t>(kSent));
  EXPECT_EQ(rx->Statistics().dropped_frames, reported);
}

TEST(SocketCanKernel, OwnFramesOnlyWhenAskedFor) {
  SocketCanOptions own;
  own.receive_own_frames = true;
  OPEN_OR_SKIP(self, own);
  CanFrame frame;
  frame.id = 0x55;
  frame.length = 1;
  ASSERT_EQ(self->Send(frame, 1'000'000'000), CanStatus::kOk);
  CanFrame back;
  ASSERT_EQ(self->Receive(&back, 1'000'000'000, nullptr), CanStatus::kOk);
  EXPECT_EQ(back.id, 0x55u);
}

TEST(SocketCanKernel, ClassicOnlyOptionRefusesFdFrames) {
  SocketCanOptions classic;
  classic.fd = false;
  OPEN_OR_SKIP(bus, classic);
  EXPECT_FALSE(bus->SupportsFd());
  CanFrame frame;
  frame.fd = true;
  frame.length = 12;
  EXPECT_EQ(bus->Send(frame, 0), CanStatus::kInvalidFrame);
  std::printf("interface %s: State()=%s\n", bus->interface_name().c_str(),
              std::string(hw::ToString(bus->State())).c_str());
}

}  // namespace
}  // namespace hrgbench::drivers::socketcan
