#pragma once
// SocketCanBus: hw::CanBus over a Linux CAN_RAW socket bound to one interface (can0, vcan0, ...).
// The Linux CAN ABI stays in the .cpp files: this header includes no vendor header.
//
// Behaviour behind the CanBus contract (hrgbench/hw/can_bus.hpp):
//   - Open() configures the socket and reads back what matters (CAN FD); every failure is a
//     message naming the interface (no AF_CAN in the kernel, no such interface, not a CAN
//     interface, interface down).
//   - CAN FD is enabled (CAN_RAW_FD_FRAMES) when options.fd and the interface MTU is CANFD_MTU.
//   - Send: non-blocking write; ENOBUFS (qdisc queue full: POLLOUT cannot be trusted for it) is
//     retried every enobufs_retry_interval_ns, EAGAIN (socket send buffer full) after
//     poll(POLLOUT), both until the timeout, then kBufferFull. ENETDOWN after a bus-off report
//     gives kBusOff.
//   - Receive: recvmsg with a msghdr, iovec and control buffer wired ONCE at Open; ppoll for the
//     timeout (ns resolution). No allocation. Error frames (CAN_RAW_ERR_FILTER: controller,
//     bus-off, restarted, error counters) update State() through DecodeErrorFrame and are counted,
//     not returned; going bus-off ends the call with kBusOff.
//   - Timestamps: SO_TIMESTAMPING, the raw hardware stamp when the interface gives one
//     (kHardware, the controller's clock), else the kernel's software stamp (kSoftware,
//     CLOCK_REALTIME); if SO_TIMESTAMPING is refused, SO_TIMESTAMPNS (kSoftware). kNone: the
//     CLOCK_REALTIME at return.
//   - Drops: SO_RXQ_OVFL's cumulative count of frames the socket dropped; the difference since
//     the previous frame is ReceiveInfo::dropped_frames and adds to Statistics().dropped_frames.
//   - Timeouts are measured on CLOCK_MONOTONIC.
// Threads: one thread Sends while another Receives; Statistics/State/SupportsFd/SetFilters from any
// thread. Receive is not re-entrant (one receive buffer).

#include <atomic>
#include <cstdint>
#include <expected>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "hrgbench/hw/can_bus.hpp"

namespace hrgbench::drivers::socketcan {

struct SocketCanOptions {
  // Use CAN FD when the interface's MTU allows it. False: classic frames only, even on FD links.
  bool fd = true;
  // Receive this socket's own frames (CAN_RAW_RECV_OWN_MSGS). Off, as on a CAN bus.
  bool receive_own_frames = false;
  // Also report CAN_ERR_PROT / CAN_ERR_BUSERROR frames. Off: a bad bus floods them, and the state
  // machine needs only controller, bus-off and restart reports.
  bool report_bus_errors = false;
  // SO_RCVBUF in bytes; 0 keeps the kernel default (net.core.rmem_default, ~200 frames). The kernel
  // caps it at net.core.rmem_max and doubles it for bookkeeping.
  int receive_buffer_bytes = 0;
  // Sleep between retries of a send refused with ENOBUFS. 100 µs: about one frame time at
  // 1 Mbit/s, so a freed queue slot is used promptly without spinning.
  std::int64_t enobufs_retry_interval_ns = 100'000;

  bool IsValid(std::string* why) const;
};

class SocketCanBus final : public hw::CanBus {
 public:
  // Opens and configures a CAN_RAW socket on `interface_name`. Not real-time (allocates, syscalls).
  static std::expected<std::unique_ptr<SocketCanBus>, std::string> Open(
      std::string_view interface_name, const SocketCanOptions& options = {});
  ~SocketCanBus() override;  // closes the socket
  SocketCanBus(const SocketCanBus&) = delete;
  SocketCanBus& operator=(const SocketCanBus&) = delete;

  hw::CanStatus Send(const hw::CanFrame& frame, std::int64_t timeout_ns) noexcept override;
  hw::CanStatus Receive(hw::CanFrame* frame, std::int64_t timeout_ns,
                        hw::ReceiveInfo* info) noexcept override;
  hw::CanStatus SetFilters(std::span<const hw::CanFilter> filters) noexcept override;
  hw::CanBusStatistics Statistics() const noexcept override;
  hw::CanBusState State() const noexcept override;
  bool SupportsFd() const noexcept override { return fd_frames_; }

  const std::string& interface_name() const noexcept { return interface_name_; }

 private:
  struct ReceiveBuffers;  // msghdr, iovec, frame and control buffer: wired once at Open
  struct Counters {
    std::atomic<std::uint64_t> frames_sent{0}, frames_received{0}, error_frames{0}, send_errors{0},
        receive_errors{0}, invalid_frames{0}, dropped_frames{0}, buffer_full_retries{0},
        buffer_full{0}, timeouts{0};
  };

  SocketCanBus(int socket_fd, std::string interface_name, bool fd_frames,
               const SocketCanOptions& options);
  // Handles one received datagram of `bytes`; returns kOk with *frame filled, kBusOff, or kError
  // (meaning "nothing for the caller, keep waiting").
  hw::CanStatus TakeDatagram(long bytes, hw::CanFrame* frame, hw::ReceiveInfo* info) noexcept;

  int socket_fd_;
  std::string interface_name_;
  bool fd_frames_;
  SocketCanOptions options_;
  std::unique_ptr<ReceiveBuffers> rx_;
  std::uint32_t last_overflow_count_ = 0;  // SO_RXQ_OVFL value of the previous datagram
  std::atomic<hw::CanBusState> state_{hw::CanBusState::kUnknown};
  Counters counters_;
};

}  // namespace hrgbench::drivers::socketcan
