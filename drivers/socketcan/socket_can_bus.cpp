// SocketCanBus: the real-time path (Send, Receive, SetFilters). Setup is in socket_can_open.cpp.

#include "socketcan/socket_can_bus.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <ctime>

#include "socketcan/error_frame.hpp"
#include "socketcan/linux_can_frame.hpp"

namespace hrgbench::drivers::socketcan {
namespace {

using hw::CanBusState;
using hw::CanStatus;

constexpr std::int64_t kNsPerS = 1'000'000'000;

std::int64_t NowNs(clockid_t clock) noexcept {
  timespec ts{};
  clock_gettime(clock, &ts);
  return std::int64_t{ts.tv_sec} * kNsPerS + ts.tv_nsec;
}

std::int64_t ToNs(const timespec& ts) noexcept {
  return std::int64_t{ts.tv_sec} * kNsPerS + ts.tv_nsec;
}

timespec ToTimespec(std::int64_t ns) noexcept {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(ns / kNsPerS);
  ts.tv_nsec = static_cast<long>(ns % kNsPerS);
  return ts;
}

// Waits for `events` on `fd` for at most `timeout_ns`. >0 ready, 0 timeout, <0 error (errno).
int PollFor(int fd, short events, std::int64_t timeout_ns) noexcept {
  pollfd pfd{fd, events, 0};
  const timespec ts = ToTimespec(timeout_ns > 0 ? timeout_ns : 0);
  return ppoll(&pfd, 1, &ts, nullptr);
}

// struct scm_timestamping: software, (deprecated), raw hardware stamps.
struct ScmTimestamping {
  timespec ts[3];
};

}  // namespace

struct SocketCanBus::ReceiveBuffers {
  canfd_frame frame{};
  sockaddr_can address{};
  iovec iov{};
  msghdr message{};
  // Room for SCM_TIMESTAMPING (3 timespecs) and SO_RXQ_OVFL (a u32), with cmsg headers and padding.
  alignas(cmsghdr) std::array<unsigned char, 256> control{};

  ReceiveBuffers() {
    iov.iov_base = &frame;
    iov.iov_len = sizeof frame;
    message.msg_name = &address;
    message.msg_namelen = sizeof address;
    message.msg_iov = &iov;
    message.msg_iovlen = 1;
    message.msg_control = control.data();
    message.msg_controllen = control.size();
  }
};

SocketCanBus::SocketCanBus(int socket_fd, std::string interface_name, bool fd_frames,
                           const SocketCanOptions& options)
    : socket_fd_(socket_fd),
      interface_name_(std::move(interface_name)),
      fd_frames_(fd_frames),
      options_(options),
      rx_(std::make_unique<ReceiveBuffers>()) {}

SocketCanBus::~SocketCanBus() {
  if (socket_fd_ >= 0) close(socket_fd_);
}

CanStatus SocketCanBus::Send(const hw::CanFrame& frame, std::int64_t timeout_ns) noexcept {
  if (socket_fd_ < 0) return CanStatus::kNotOpen;
  if (!hw::IsValidCanFrame(frame, fd_frames_)) {
    counters_.invalid_frames.fetch_add(1, std::memory_order_relaxed);
    return CanStatus::kInvalidFrame;
  }
  canfd_frame wire;
  const std::size_t bytes = ToLinuxFrame(frame, &wire);
  const std::int64_t deadline_ns = NowNs(CLOCK_MONOTONIC) + (timeout_ns > 0 ? timeout_ns : 0);
  for (;;) {
    const ssize_t written = write(socket_fd_, &wire, bytes);
    if (written == static_cast<ssize_t>(bytes)) {
      counters_.frames_sent.fetch_add(1, std::memory_order_relaxed);
      return CanStatus::kOk;
    }
    const int error = written < 0 ? errno : EIO;  // a short write of a CAN datagram is a fault
    if (error == EINTR) continue;
    if (error == ENOBUFS || error == EAGAIN) {
      const std::int64_t remaining_ns = deadline_ns - NowNs(CLOCK_MONOTONIC);
      if (remaining_ns <= 0) {
        counters_.buffer_full.fetch_add(1, std::memory_order_relaxed);
        return CanStatus::kBufferFull;
      }
      counters_.buffer_full_retries.fetch_add(1, std::memory_order_relaxed);
      if (error == EAGAIN) {
        PollFor(socket_fd_, POLLOUT, remaining_ns);
      } else {
        const std::int64_t pause_ns = std::min(remaining_ns, options_.enobufs_retry_interval_ns);
        const timespec pause = ToTimespec(pause_ns);
        clock_nanosleep(CLOCK_MONOTONIC, 0, &pause, nullptr);
      }
      continue;
    }
    counters_.send_errors.fetch_add(1, std::memory_order_relaxed);
    if (error == ENETDOWN && state_.load() == CanBusState::kBusOff) return CanStatus::kBusOff;
    return CanStatus::kError;
  }
}

CanStatus SocketCanBus::TakeDatagram(long bytes, hw::CanFrame* frame,
                                     hw::ReceiveInfo* info) noexcept {
  hw::ReceiveInfo stamp;
  msghdr& message = rx_->message;
  for (cmsghdr* c = CMSG_FIRSTHDR(&message); c != nullptr; c = CMSG_NXTHDR(&message, c)) {
    if (c->cmsg_level != SOL_SOCKET) continue;
    if (c->cmsg_type == SO_RXQ_OVFL) {
      std::uint32_t overflow_count = 0;
      std::memcpy(&overflow_count, CMSG_DATA(c), sizeof overflow_count);
      // Unsigned difference: correct across the counter's wrap-around.
      const std::uint32_t dropped = overflow_count - last_overflow_count_;
      last_overflow_count_ = overflow_count;
      stamp.dropped_frames = dropped;
      counters_.dropped_frames.fetch_add(dropped, std::memory_order_relaxed);
    } else if (c->cmsg_type == SO_TIMESTAMPING) {
      ScmTimestamping stamps;
      std::memcpy(&stamps, CMSG_DATA(c), sizeof stamps);
      if (stamps.ts[2].tv_sec != 0 || stamps.ts[2].tv_nsec != 0) {
        stamp.timestamp_ns = ToNs(stamps.ts[2]);
        stamp.timestamp_source = hw::TimestampSource::kHardware;
      } else if (stamps.ts[0].tv_sec != 0 || stamps.ts[0].tv_nsec != 0) {
        stamp.timestamp_ns = ToNs(stamps.ts[0]);
        stamp.timestamp_source = hw::TimestampSource::kSoftware;
      }
    } else if (c->cmsg_type == SO_TIMESTAMPNS) {
      timespec ts;
      std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
      stamp.timestamp_ns = ToNs(ts);
      stamp.timestamp_source = hw::TimestampSource::kSoftware;
    }
  }
  if (stamp.timestamp_source == hw::TimestampSource::kNone)
    stamp.timestamp_ns = NowNs(CLOCK_REALTIME);

  hw::CanFrame received;
  if (!FromLinuxFrame(rx_->frame, static_cast<std::size_t>(bytes), &received)) {
    counters_.invalid_frames.fetch_add(1, std::memory_order_relaxed);
    return CanStatus::kError;
  }
  if (received.error) {
    counters_.error_frames.fetch_add(1, std::memory_order_relaxed);
    const CanBusState before = state_.load();
    const ErrorFrameReport report = DecodeErrorFrame(
        received.id, std::span<const std::uint8_t, 8>(received.data.data(), 8), before);
    state_.store(report.state);
    if (report.state == CanBusState::kBusOff && before != CanBusState::kBusOff) {
      return CanStatus::kBusOff;
    }
    return CanStatus::kError;
  }
  *frame = received;
  if (info != nullptr) *info = stamp;
  counters_.frames_received.fetch_add(1, std::memory_order_relaxed);
  return CanStatus::kOk;
}

CanStatus SocketCanBus::Receive(hw::CanFrame* frame, std::int64_t timeout_ns,
                                hw::ReceiveInfo* info) noexcept {
  if (socket_fd_ < 0) return CanStatus::kNotOpen;
  if (frame == nullptr) return CanStatus::kInvalidArgument;
  const std::int64_t deadline_ns = NowNs(CLOCK_MONOTONIC) + (timeout_ns > 0 ? timeout_ns : 0);
  for (;;) {
    // Only the lengths the kernel overwrites are reset; the buffers themselves were wired at Open.
    rx_->message.msg_controllen = rx_->control.size();
    rx_->message.msg_namelen = sizeof rx_->address;
    rx_->message.msg_flags = 0;
    const ssize_t bytes = recvmsg(socket_fd_, &rx_->message, MSG_DONTWAIT);
    if (bytes >= 0) {
      const CanStatus status = TakeDatagram(bytes, frame, info);
      if (status != CanStatus::kError) return status;
      continue;  // an error frame or a malformed datagram: keep waiting for a frame
    }
    const int error = errno;
    if (error == EINTR) continue;
    if (error != EAGAIN && error != EWOULDBLOCK) {
      counters_.receive_errors.fetch_add(1, std::memory_order_relaxed);
      if (error == ENETDOWN && state_.load() == CanBusState::kBusOff) return CanStatus::kBusOff;
      return CanStatus::kError;
    }
    const std::int64_t remaining_ns = deadline_ns - NowNs(CLOCK_MONOTONIC);
    if (remaining_ns <= 0) {
      if (state_.load() == CanBusState::kBusOff) return CanStatus::kBusOff;
      counters_.timeouts.fetch_add(1, std::memory_order_relaxed);
      return CanStatus::kTimeout;
    }
    if (PollFor(socket_fd_, POLLIN, remaining_ns) < 0 && errno != EINTR) {
      counters_.receive_errors.fetch_add(1, std::memory_order_relaxed);
      return CanStatus::kError;
    }
  }
}

CanStatus SocketCanBus::SetFilters(std::span<const hw::CanFilter> filters) noexcept {
  if (socket_fd_ < 0) return CanStatus::kNotOpen;
  if (filters.size() > hw::kMaxCanFilters) return CanStatus::kInvalidArgument;
  std::array<can_filter, hw::kMaxCanFilters> raw{};
  for (std::size_t i = 0; i < filters.size(); ++i) {
    // CAN_EFF_FLAG in both id and mask: the frame format must match, as the CanFilter contract
    // says. CAN_RTR_FLAG is left out of the mask: data and remote frames both pass.
    raw[i].can_id = filters[i].id | (filters[i].extended ? CAN_EFF_FLAG : 0u);
    raw[i].can_mask = filters[i].mask | CAN_EFF_FLAG;
  }
  // Zero filters (optlen 0) make the kernel pass no frame, which is the contract for an empty span.
  const auto bytes = static_cast<socklen_t>(filters.size() * sizeof(can_filter));
  if (setsockopt(socket_fd_, SOL_CAN_RAW, CAN_RAW_FILTER, filters.empty() ? nullptr : raw.data(),
                 bytes) != 0) {
    return CanStatus::kError;
  }
  return CanStatus::kOk;
}

hw::CanBusStatistics SocketCanBus::Statistics() const noexcept {
  constexpr auto kRelaxed = std::memory_order_relaxed;
  hw::CanBusStatistics s;
  s.frames_sent = counters_.frames_sent.load(kRelaxed);
  s.frames_received = counters_.frames_received.load(kRelaxed);
  s.error_frames = counters_.error_frames.load(kRelaxed);
  s.send_errors = counters_.send_errors.load(kRelaxed);
  s.receive_errors = counters_.receive_errors.load(kRelaxed);
  s.invalid_frames = counters_.invalid_frames.load(kRelaxed);
  s.dropped_frames = counters_.dropped_frames.load(kRelaxed);
  s.buffer_full_retries = counters_.buffer_full_retries.load(kRelaxed);
  s.buffer_full = counters_.buffer_full.load(kRelaxed);
  s.timeouts = counters_.timeouts.load(kRelaxed);
  return s;
}

CanBusState SocketCanBus::State() const noexcept { return state_.load(); }

}  // namespace hrgbench::drivers::socketcan
