// Open's failures are values with a message naming the interface, on any kernel: without AF_CAN
// the socket fails, with it the interface lookup does.

#include <gtest/gtest.h>

#include "socketcan/socket_can_bus.hpp"

namespace hrgbench::drivers::socketcan {
namespace {

TEST(SocketCanOpen, AMissingInterfaceIsAnErrorNamingIt) {
  const auto bus = SocketCanBus::Open("hrgnosuch0");
  ASSERT_FALSE(bus.has_value());
  EXPECT_NE(bus.error().find("'hrgnosuch0'"), std::string::npos) << bus.error();
}

TEST(SocketCanOpen, BadNamesAndOptionsAreRefusedBeforeAnySocket) {
  EXPECT_FALSE(SocketCanBus::Open("").has_value());
  const auto too_long = SocketCanBus::Open("a_name_longer_than_ifnamsiz");
  ASSERT_FALSE(too_long.has_value());
  EXPECT_NE(too_long.error().find("characters"), std::string::npos) << too_long.error();
  SocketCanOptions options;
  options.enobufs_retry_interval_ns = 0;
  const auto bad = SocketCanBus::Open("vcan0", options);
  ASSERT_FALSE(bad.has_value());
  EXPECT_NE(bad.error().find("enobufs_retry_interval_ns"), std::string::npos) << bad.error();
}

}  // namespace
}  // namespace hrgbench::drivers::socketcan
