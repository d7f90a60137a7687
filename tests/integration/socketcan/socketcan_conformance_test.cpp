// The CanBus conformance suite against SocketCAN: two CAN_RAW sockets on one vcan interface (the
// kernel loops each frame back to the interface's other sockets).

#include "can_bus_conformance_tests.hpp"
#include "socketcan/socket_can_bus.hpp"
#include "vcan_name.hpp"

namespace hrgbench::testing {
namespace {

using drivers::socketcan::SocketCanBus;

std::expected<CanBusPair, std::string> MakeSocketCanPair() {
  const std::string name = VcanName();
  auto a = SocketCanBus::Open(name);
  if (!a) return std::unexpected(a.error());
  auto b = SocketCanBus::Open(name);
  if (!b) return std::unexpected(b.error());
  CanBusPair pair;
  pair.a = std::move(*a);
  pair.b = std::move(*b);
  return pair;
}

INSTANTIATE_TEST_SUITE_P(SocketCan, CanBusConformanceTest,
                         ::testing::Values(CanBusConformanceParam{"vcan", &MakeSocketCanPair,
                                                                  VcanRequired()}),
                         CanBusConformanceName);
// vcan0 is brought up CAN FD capable (mtu 72) by scripts/run-in-kernel.sh.
INSTANTIATE_TEST_SUITE_P(SocketCan, CanFdConformanceTest,
                         ::testing::Values(CanBusConformanceParam{"vcan", &MakeSocketCanPair,
                                                                  VcanRequired()}),
                         CanBusConformanceName);

}  // namespace
}  // namespace hrgbench::testing
