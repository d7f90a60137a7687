// SocketCanBus setup: open, configure and read back the CAN_RAW socket. Each step that can fail
// says which interface and what to do about it.

#include <linux/can/error.h>
#include <linux/net_tstamp.h>
#include <net/if.h>
#include <net/if_arp.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <utility>

#include "socketcan/linux_can_frame.hpp"
#include "socketcan/socket_can_bus.hpp"

namespace hrgbench::drivers::socketcan {
namespace {

// Closes the socket unless released: every early return of Open cleans up.
class SocketGuard {
 public:
  explicit SocketGuard(int fd) : fd_(fd) {}
  ~SocketGuard() {
    if (fd_ >= 0) close(fd_);
  }
  SocketGuard(const SocketGuard&) = delete;
  SocketGuard& operator=(const SocketGuard&) = delete;
  int get() const { return fd_; }
  int release() { return std::exchange(fd_, -1); }

 private:
  int fd_;
};

std::string Errno(int error) { return std::string(std::strerror(error)); }

template <typename T>
bool SetOption(int fd, int level, int name, const T& value) {
  return setsockopt(fd, level, name, &value, sizeof value) == 0;
}

}  // namespace

bool SocketCanOptions::IsValid(std::string* why) const {
  if (receive_buffer_bytes < 0) {
    if (why != nullptr) *why = "receive_buffer_bytes must be >= 0 (0 = kernel default)";
    return false;
  }
  if (enobufs_retry_interval_ns <= 0) {
    if (why != nullptr) *why = "enobufs_retry_interval_ns must be > 0";
    return false;
  }
  return true;
}

std::expected<std::unique_ptr<SocketCanBus>, std::string> SocketCanBus::Open(
    std::string_view interface_name, const SocketCanOptions& options) {
  const std::string name(interface_name);
  const std::string where = "SocketCAN interface '" + name + "': ";
  std::string why;
  if (!options.IsValid(&why)) return std::unexpected(where + "invalid options: " + why);
  if (name.empty() || name.size() >= IFNAMSIZ) {
    return std::unexpected(where + "an interface name has 1 to " + std::to_string(IFNAMSIZ - 1) +
                           " characters");
  }

  SocketGuard socket_fd(socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW));
  if (socket_fd.get() < 0) {
    const int error = errno;
    std::string hint;
    if (error == EAFNOSUPPORT) hint = " (this kernel has no AF_CAN: load the 'can' module)";
    if (error == EPROTONOSUPPORT) hint = " (no CAN_RAW protocol: load the 'can-raw' module)";
    return std::unexpected(where + "cannot open a CAN_RAW socket: " + Errno(error) + hint);
  }

  ifreq request{};
  std::memcpy(request.ifr_name, name.c_str(), name.size() + 1);
  if (ioctl(socket_fd.get(), SIOCGIFINDEX, &request) != 0) {
    const int error = errno;
    return std::unexpected(where + "no such interface: " + Errno(error) +
                           " (for a virtual one: ip link add dev " + name + " type vcan)");
  }
  const int interface_index = request.ifr_ifindex;
  if (ioctl(socket_fd.get(), SIOCGIFHWADDR, &request) == 0 &&
      request.ifr_hwaddr.sa_family != ARPHRD_CAN) {
    return std::unexpected(where + "not a CAN interface (link type " +
                           std::to_string(request.ifr_hwaddr.sa_family) + ")");
  }
  if (ioctl(socket_fd.get(), SIOCGIFFLAGS, &request) == 0 && (request.ifr_flags & IFF_UP) == 0) {
    return std::unexpected(where + "interface is down (ip link set " + name + " up)");
  }
  if (ioctl(socket_fd.get(), SIOCGIFMTU, &request) != 0) {
    return std::unexpected(where + "cannot read the MTU: " + Errno(errno));
  }
  const bool link_is_fd = request.ifr_mtu >= static_cast<int>(kFdMtu);

  bool fd_frames = false;
  if (options.fd && link_is_fd) {
    if (!SetOption(socket_fd.get(), SOL_CAN_RAW, CAN_RAW_FD_FRAMES, 1)) {
      return std::unexpected(where + "cannot enable CAN FD frames: " + Errno(errno));
    }
    // Read back (STYLE rule 5): an older kernel may accept the option and ignore it.
    int enabled = 0;
    socklen_t length = sizeof enabled;
    getsockopt(socket_fd.get(), SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &enabled, &length);
    fd_frames = enabled != 0;
  }
  if (options.receive_own_frames &&
      !SetOption(socket_fd.get(), SOL_CAN_RAW, CAN_RAW_RECV_OWN_MSGS, 1)) {
    return std::unexpected(where + "cannot enable own-frame reception: " + Errno(errno));
  }
  can_err_mask_t error_mask = CAN_ERR_CRTL | CAN_ERR_BUSOFF | CAN_ERR_RESTARTED | CAN_ERR_CNT;
  if (options.report_bus_errors) error_mask |= CAN_ERR_PROT | CAN_ERR_BUSERROR;
  if (!SetOption(socket_fd.get(), SOL_CAN_RAW, CAN_RAW_ERR_FILTER, error_mask)) {
    return std::unexpected(where + "cannot set the error-frame filter: " + Errno(errno));
  }
  if (!SetOption(socket_fd.get(), SOL_SOCKET, SO_RXQ_OVFL, 1)) {
    return std::unexpected(where + "cannot enable the drop counter (SO_RXQ_OVFL): " + Errno(errno));
  }
  // Ask for both stamps; per frame the hardware one is used when the driver filled it in.
  const int stamping = SOF_TIMESTAMPING_RX_HARDWARE | SOF_TIMESTAMPING_RAW_HARDWARE |
                       SOF_TIMESTAMPING_RX_SOFTWARE | SOF_TIMESTAMPING_SOFTWARE;
  if (!SetOption(socket_fd.get(), SOL_SOCKET, SO_TIMESTAMPING, stamping) &&
      !SetOption(socket_fd.get(), SOL_SOCKET, SO_TIMESTAMPNS, 1)) {
    return std::unexpected(where + "cannot enable receive timestamps: " + Errno(errno));
  }
  if (options.receive_buffer_bytes > 0 &&
      !SetOption(socket_fd.get(), SOL_SOCKET, SO_RCVBUF, options.receive_buffer_bytes)) {
    return std::unexpected(where + "cannot set SO_RCVBUF: " + Errno(errno));
  }

  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = interface_index;
  if (bind(socket_fd.get(), reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    return std::unexpected(where + "cannot bind: " + Errno(errno));
  }
  return std::unique_ptr<SocketCanBus>(
      new SocketCanBus(socket_fd.release(), name, fd_frames, options));
}

}  // namespace hrgbench::drivers::socketcan
