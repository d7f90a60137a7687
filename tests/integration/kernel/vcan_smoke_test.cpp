// vcan smoke test: proves that the kernel harness (scripts/run-in-kernel.sh) gives a test binary a
// working, CAN FD capable vcan0. Self-contained on purpose (raw sockets, no hrgbench driver), so a
// failure here points at the harness or the kernel, never at the SocketCAN transport under test.
//
// Two CAN_RAW sockets on the same interface: frames sent on one come back on the other through the
// interface's loopback, which is how vcan delivers. Checks: 10 000 classic and 10 000 64-byte FD
// frames arrive complete, in order and unchanged, the kernel reports no receive-queue drops
// (SO_RXQ_OVFL), and a filter rejects ids that do not match.
//
// Outside the VM this binary normally has no AF_CAN: it then skips, unless HRGBENCH_REQUIRE_VCAN=1
// (set by the VM's /init), where a missing vcan0 is a failure. HRGBENCH_CAN_IFACE overrides vcan0.

#include <gtest/gtest.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <expected>
#include <string>
#include <utility>

namespace hrgbench {
namespace {

constexpr int kFramesPerKind = 10'000;
// Frames in flight between a send burst and its receive: well under the default receive buffer
// (about 200 frames at ~1 KiB of skb truesize each), so a healthy kernel never drops one.
constexpr int kBurst = 32;
constexpr int kReceiveTimeout_ms = 2'000;

std::string ErrnoText(const char* what) { return std::string(what) + ": " + std::strerror(errno); }

// can-utils notation (`123#DEADBEEF`, `12345678##1DEADBEEF` for FD) so a failure prints frames that
// can be pasted into cansend.
std::string CanUtils(const canfd_frame& frame, bool is_fd) {
  char text[16 + 2 * CANFD_MAX_DLEN + 4];
  int n = (frame.can_id & CAN_EFF_FLAG)
              ? std::snprintf(text, sizeof text, "%08X", frame.can_id & CAN_EFF_MASK)
              : std::snprintf(text, sizeof text, "%03X", frame.can_id & CAN_SFF_MASK);
  n += is_fd ? std::snprintf(text + n, sizeof text - n, "##%X", frame.flags & 0xF)
             : std::snprintf(text + n, sizeof text - n, "#");
  for (int i = 0; i < frame.len; ++i) {
    n += std::snprintf(text + n, sizeof text - n, "%02X", frame.data[i]);
  }
  return text;
}

// One CAN_RAW socket bound to an interface. The receive message and its control buffer are wired
// once here (as candump does), not per frame.
class RawSocket {
 public:
  static std::expected<RawSocket, std::string> Open(const std::string& iface, bool fd_frames) {
    RawSocket s;
    s.fd_ = socket(PF_CAN, SOCK_RAW, CAN_RAW);
    if (s.fd_ < 0) return std::unexpected(ErrnoText("socket(PF_CAN, SOCK_RAW, CAN_RAW)"));
    const int on = 1;
    if (fd_frames && setsockopt(s.fd_, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on) != 0) {
      return std::unexpected(ErrnoText("setsockopt(CAN_RAW_FD_FRAMES)"));
    }
    if (setsockopt(s.fd_, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on) != 0) {
      return std::unexpected(ErrnoText("setsockopt(SO_RXQ_OVFL)"));
    }
    sockaddr_can addr{};
    addr.can_family = AF_CAN;
    addr.can_ifindex = static_cast<int>(if_nametoindex(iface.c_str()));
    if (addr.can_ifindex == 0)
      return std::unexpected(ErrnoText(("if_nametoindex " + iface).c_str()));
    if (bind(s.fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
      return std::unexpected(ErrnoText("bind"));
    }
    return s;
  }

  RawSocket(RawSocket&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  RawSocket& operator=(RawSocket&&) = delete;
  RawSocket(const RawSocket&) = delete;
  RawSocket& operator=(const RawSocket&) = delete;
  ~RawSocket() {
    if (fd_ >= 0) close(fd_);
  }

  bool SetFilter(const can_filter& filter) {
    return setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, &filter, sizeof filter) == 0;
  }

  // Sends one frame; vcan may answer ENOBUFS when its queue is full, which is retried after poll.
  bool Send(const canfd_frame& frame, bool is_fd) {
    const std::size_t size = is_fd ? CANFD_MTU : CAN_MTU;
    for (int attempt = 0; attempt < 1000; ++attempt) {
      const ssize_t n = write(fd_, &frame, size);
      if (n == static_cast<ssize_t>(size)) return true;
      if (n >= 0 || errno != ENOBUFS) return false;
      pollfd p{fd_, POLLOUT, 0};
      poll(&p, 1, 1);
    }
    return false;
  }

  // Receives one frame into *frame; returns its size (CAN_MTU or CANFD_MTU), 0 on timeout, -1 on
  // error. Records the kernel's cumulative drop count for this socket.
  ssize_t Receive(canfd_frame* frame, int timeout_ms) {
    pollfd p{fd_, POLLIN, 0};
    const int ready = poll(&p, 1, timeout_ms);
    if (ready <= 0) return ready;
    iov_ = {frame, sizeof *frame};
    msg_.msg_iov = &iov_;
    msg_.msg_iovlen = 1;
    msg_.msg_control = control_.data();
    msg_.msg_controllen = control_.size();
    const ssize_t n = recvmsg(fd_, &msg_, 0);
    if (n < 0) return -1;
    for (cmsghdr* c = CMSG_FIRSTHDR(&msg_); c != nullptr; c = CMSG_NXTHDR(&msg_, c)) {
      if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_RXQ_OVFL) {
        std::memcpy(&kernel_drops_, CMSG_DATA(c), sizeof kernel_drops_);
      }
    }
    return n;
  }

  std::uint32_t kernel_drops() const { return kernel_drops_; }

 private:
  RawSocket() = default;

  int fd_ = -1;
  iovec iov_{};
  msghdr msg_{};
  alignas(cmsghdr) std::array<unsigned char, CMSG_SPACE(sizeof(std::uint32_t))> control_{};
  std::uint32_t kernel_drops_ = 0;
};

std::string Interface() {
  const char* iface = std::getenv("HRGBENCH_CAN_IFACE");
  return iface != nullptr && *iface != '\0' ? iface : "vcan0";
}

bool VcanRequired() {
  const char* required = std::getenv("HRGBENCH_REQUIRE_VCAN");
  return required != nullptr && std::string(required) == "1";
}

// Frame number i of a kind: the sequence number in the first 4 bytes (little-endian), then a
// pattern that changes with i and with the byte's position, so a reordered, truncated or stale
// frame differs.
canfd_frame MakeFrame(std::uint32_t i, bool is_fd) {
  canfd_frame frame{};
  if (is_fd) {
    frame.can_id = CAN_EFF_FLAG | ((0x1000000u + i) & CAN_EFF_MASK);
    frame.len = CANFD_MAX_DLEN;
    frame.flags = CANFD_BRS;
  } else {
    frame.can_id = 0x100u + (i % 0x600u);
    frame.len = static_cast<std::uint8_t>(4 + i % 5);  // 4..8 bytes: short frames too
  }
  for (int b = 0; b < 4; ++b) frame.data[b] = static_cast<std::uint8_t>(i >> (8 * b));
  for (int b = 4; b < frame.len; ++b) frame.data[b] = static_cast<std::uint8_t>(i * 31u + b * 7u);
  return frame;
}

bool SameFrame(const canfd_frame& a, const canfd_frame& b, bool is_fd) {
  // Only BRS and ESI are the sender's to set; newer kernels add CANFD_FDF on receive.
  const auto flags = [is_fd](const canfd_frame& f) {
    return is_fd ? f.flags & (CANFD_BRS | CANFD_ESI) : 0;
  };
  return a.can_id == b.can_id && a.len == b.len && flags(a) == flags(b) &&
         std::memcmp(a.data, b.data, a.len) == 0;
}

class VcanSmoke : public ::testing::Test {
 protected:
  void SetUp() override {
    auto probe = RawSocket::Open(Interface(), /*fd_frames=*/true);
    if (!probe) {
      if (VcanRequired()) FAIL() << "no usable " << Interface() << ": " << probe.error();
      GTEST_SKIP() << "no usable " << Interface() << " (" << probe.error()
                   << "); run through scripts/run-in-kernel.sh (ctest -L kernel)";
    }
  }

  // Sends kFramesPerKind frames of one kind in bursts and checks each received frame against the
  // one expected next. Returns after the first mismatch so the log stays readable.
  void RoundTrip(bool is_fd) {
    auto tx = RawSocket::Open(Interface(), is_fd);
    auto rx = RawSocket::Open(Interface(), is_fd);
    ASSERT_TRUE(tx.has_value()) << tx.error();
    ASSERT_TRUE(rx.has_value()) << rx.error();
    const std::size_t mtu = is_fd ? CANFD_MTU : CAN_MTU;
    std::uint32_t next_rx = 0;
    for (std::uint32_t next_tx = 0; next_tx < kFramesPerKind;) {
      for (int k = 0; k < kBurst && next_tx < kFramesPerKind; ++k, ++next_tx) {
        ASSERT_TRUE(tx->Send(MakeFrame(next_tx, is_fd), is_fd))
            << ErrnoText("write") << " at frame " << next_tx;
      }
      while (next_rx < next_tx) {
        canfd_frame got{};
        const ssize_t n = rx->Receive(&got, kReceiveTimeout_ms);
        ASSERT_GT(n, 0) << (n == 0 ? "timeout" : ErrnoText("recvmsg")) << " waiting for frame "
                        << next_rx << " (kernel drops " << rx->kernel_drops() << ")";
        ASSERT_EQ(static_cast<std::size_t>(n), mtu) << "frame " << next_rx;
        const canfd_frame want = MakeFrame(next_rx, is_fd);
        ASSERT_TRUE(SameFrame(got, want, is_fd))
            << "frame " << next_rx << ": got " << CanUtils(got, is_fd) << ", expected "
            << CanUtils(want, is_fd);
        ++next_rx;
      }
    }
    EXPECT_EQ(next_rx, static_cast<std::uint32_t>(kFramesPerKind));
    EXPECT_EQ(rx->kernel_drops(), 0u);
    canfd_frame extra{};
    EXPECT_EQ(rx->Receive(&extra, 50), 0) << "unexpected frame " << CanUtils(extra, is_fd);
  }
};

TEST_F(VcanSmoke, ClassicFramesArriveCompleteInOrderAndUnchanged) { RoundTrip(/*is_fd=*/false); }

TEST_F(VcanSmoke, FdFramesOf64BytesArriveCompleteInOrderAndUnchanged) { RoundTrip(/*is_fd=*/true); }

TEST_F(VcanSmoke, FilterPassesMatchingIdAndRejectsTheRest) {
  auto tx = RawSocket::Open(Interface(), /*fd_frames=*/false);
  auto rx = RawSocket::Open(Interface(), /*fd_frames=*/false);
  ASSERT_TRUE(tx.has_value()) << tx.error();
  ASSERT_TRUE(rx.has_value()) << rx.error();
  // Exactly standard id 0x123, data frames only: 0x123 with EFF set (extended 0x00000123) and RTR
  // frames must not pass either.
  const can_filter only_0x123{0x123, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG};
  ASSERT_TRUE(rx->SetFilter(only_0x123)) << ErrnoText("setsockopt(CAN_RAW_FILTER)");

  constexpr std::uint32_t kRounds = 200;
  const canid_t rejected[] = {0x122, 0x124, 0x523, CAN_EFF_FLAG | 0x123, CAN_RTR_FLAG | 0x123};
  for (std::uint32_t i = 0; i < kRounds; ++i) {
    for (const canid_t id : rejected) {
      canfd_frame other{};
      other.can_id = id;
      other.len = 2;
      ASSERT_TRUE(tx->Send(other, false)) << ErrnoText("write");
    }
    canfd_frame match = MakeFrame(i, false);
    match.can_id = 0x123;
    ASSERT_TRUE(tx->Send(match, false)) << ErrnoText("write");
    // Drain as we go so the receive buffer never limits the test.
    canfd_frame got{};
    ASSERT_EQ(rx->Receive(&got, kReceiveTimeout_ms), static_cast<ssize_t>(CAN_MTU))
        << "waiting for matching frame " << i;
    ASSERT_TRUE(SameFrame(got, match, false))
        << "got " << CanUtils(got, false) << ", expected " << CanUtils(match, false);
  }
  canfd_frame extra{};
  EXPECT_EQ(rx->Receive(&extra, 50), 0) << "filter let through " << CanUtils(extra, false);
  EXPECT_EQ(rx->kernel_drops(), 0u);
}

// A socket without CAN_RAW_FD_FRAMES must never see FD frames (the kernel drops them for it), while
// classic frames still arrive: the transport relies on this to run classic-only on an FD bus.
TEST_F(VcanSmoke, ClassicOnlySocketDoesNotReceiveFdFrames) {
  auto tx = RawSocket::Open(Interface(), /*fd_frames=*/true);
  auto rx = RawSocket::Open(Interface(), /*fd_frames=*/false);
  ASSERT_TRUE(tx.has_value()) << tx.error();
  ASSERT_TRUE(rx.has_value()) << rx.error();
  ASSERT_TRUE(tx->Send(MakeFrame(1, /*is_fd=*/true), true)) << ErrnoText("write");
  const canfd_frame classic = MakeFrame(2, /*is_fd=*/false);
  ASSERT_TRUE(tx->Send(classic, false)) << ErrnoText("write");
  canfd_frame got{};
  ASSERT_EQ(rx->Receive(&got, kReceiveTimeout_ms), static_cast<ssize_t>(CAN_MTU));
  EXPECT_TRUE(SameFrame(got, classic, false)) << "got " << CanUtils(got, false);
}

}  // namespace
}  // namespace hrgbench
