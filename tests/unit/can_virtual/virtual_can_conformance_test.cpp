// The CanBus conformance suite against the in-process virtual bus: an FD bus, a classic bus, and a
// bit-rate-timed bus on the steady clock (exercises the waiting path of Receive).

#include "can_bus_conformance_tests.hpp"
#include "can_virtual/virtual_can_bus.hpp"

namespace hrgbench::testing {
namespace {

using drivers::can_virtual::VirtualCanBus;
using drivers::can_virtual::VirtualCanBusOptions;

std::expected<CanBusPair, std::string> MakeVirtualPair(const VirtualCanBusOptions& options) {
  auto bus = VirtualCanBus::Create(options);
  if (!bus) return std::unexpected(bus.error());
  std::shared_ptr<VirtualCanBus> hub = std::move(*bus);
  CanBusPair pair;
  pair.a = hub->CreateEndpoint();
  pair.b = hub->CreateEndpoint();
  pair.owner = hub;
  return pair;
}

CanBusConformanceParam Param(std::string name, VirtualCanBusOptions options) {
  return {std::move(name), [options] { return MakeVirtualPair(options); }};
}

VirtualCanBusOptions Classic() {
  VirtualCanBusOptions options;
  options.fd = false;
  return options;
}

VirtualCanBusOptions Timed() {
  VirtualCanBusOptions options;
  options.nominal_bit_rate_bps = 1'000'000;
  options.data_bit_rate_bps = 8'000'000;
  return options;
}

INSTANTIATE_TEST_SUITE_P(VirtualCanBus, CanBusConformanceTest,
                         ::testing::Values(Param("fd", {}), Param("classic", Classic()),
                                           Param("timed_1mbit", Timed())),
                         CanBusConformanceName);
INSTANTIATE_TEST_SUITE_P(VirtualCanBus, CanFdConformanceTest,
                         ::testing::Values(Param("fd", {}), Param("timed_1mbit", Timed())),
                         CanBusConformanceName);

}  // namespace
}  // namespace hrgbench::testing
