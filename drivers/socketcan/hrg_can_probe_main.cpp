// hrg-can-probe: opens a CAN interface twice, sends N frames on one socket, receives them on the
// other and prints one result line. Exit status 0 only if every frame came back, in order, byte-
// exact. For the kernel (QEMU) harness and for checking a bench's adapter.
//
//   hrg-can-probe [--fd] [--count N] [interface]      (interface default: vcan0)
//   hrg-can-probe: vcan0 OK sent=10000 received=10000 fd=0 drops=0 stamps=software elapsed_ms=84.1

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "socketcan/socket_can_bus.hpp"

namespace {

using hrgbench::drivers::socketcan::SocketCanBus;
using hrgbench::hw::CanFrame;
using hrgbench::hw::CanStatus;

constexpr std::int64_t kTimeoutNs = 1'000'000'000;

int Fail(const std::string& interface_name, const std::string& why) {
  std::printf("hrg-can-probe: %s FAIL %s\n", interface_name.c_str(), why.c_str());
  return 1;
}

CanFrame Numbered(std::uint32_t n, bool fd) {
  CanFrame frame;
  frame.id = 0x100u + n % 0x600u;
  frame.fd = fd;
  frame.bit_rate_switch = fd;
  frame.length = fd ? 64 : 8;
  for (std::uint8_t i = 0; i < frame.length; ++i) {
    frame.data[i] = static_cast<std::uint8_t>((n >> (8 * (i % 4))) + i / 4);
  }
  return frame;
}

}  // namespace

int main(int argc, char** argv) {
  std::string interface_name = "vcan0";
  bool fd = false;
  long count = 10'000;
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg == "--fd") {
      fd = true;
    } else if (arg == "--count" && i + 1 < argc) {
      count = std::strtol(argv[++i], nullptr, 10);
    } else if (arg == "--help" || arg.starts_with("-")) {
      std::printf("usage: hrg-can-probe [--fd] [--count N] [interface]\n");
      return arg == "--help" ? 0 : 2;
    } else {
      interface_name = arg;
    }
  }
  if (count <= 0) return Fail(interface_name, "--count must be > 0");

  auto tx = SocketCanBus::Open(interface_name);
  if (!tx) return Fail(interface_name, tx.error());
  auto rx = SocketCanBus::Open(interface_name);
  if (!rx) return Fail(interface_name, rx.error());
  if (fd && !(*tx)->SupportsFd())
    return Fail(interface_name, "--fd: interface MTU is not CANFD_MTU");

  const auto start = std::chrono::steady_clock::now();
  const char* stamps = "none";
  std::uint64_t drops = 0;
  long received = 0;
  constexpr long kBatch = 64;  // stays well inside a default socket receive buffer
  for (long sent = 0; sent < count;) {
    for (long i = 0; i < kBatch && sent < count; ++i, ++sent) {
      const CanStatus status =
          (*tx)->Send(Numbered(static_cast<std::uint32_t>(sent), fd), kTimeoutNs);
      if (status != CanStatus::kOk) {
        return Fail(interface_name, "send " + std::to_string(sent) + ": " +
                                        std::string(hrgbench::hw::ToString(status)));
      }
    }
    for (; received < sent; ++received) {
      CanFrame frame;
      hrgbench::hw::ReceiveInfo info;
      const CanStatus status = (*rx)->Receive(&frame, kTimeoutNs, &info);
      if (status != CanStatus::kOk) {
        return Fail(interface_name, "receive " + std::to_string(received) + ": " +
                                        std::string(hrgbench::hw::ToString(status)));
      }
      drops += info.dropped_frames;
      stamps = hrgbench::hw::ToString(info.timestamp_source).data();
      const CanFrame expected = Numbered(static_cast<std::uint32_t>(received), fd);
      if (frame.id != expected.id || frame.length != expected.length || frame.fd != fd ||
          frame.data != expected.data) {
        return Fail(interface_name,
                    "frame " + std::to_string(received) + " out of order or altered");
      }
    }
  }
  const double elapsed_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "hrg-can-probe: %s OK sent=%ld received=%ld fd=%d drops=%llu stamps=%s elapsed_ms=%.1f\n",
      interface_name.c_str(), count, received, fd ? 1 : 0, static_cast<unsigned long long>(drops),
      stamps, elapsed_ms);
  return 0;
}
