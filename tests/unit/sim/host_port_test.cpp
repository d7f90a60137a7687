// HOST:PORT as the simulators' command lines take it: strict, so a typo is refused, not half-read.
#include "sim/host_port.hpp"

#include <gtest/gtest.h>

namespace hrgbench::drivers::sim {
namespace {

TEST(HostPortTest, HostAndPort) {
  const auto a = ParseHostPort("127.0.0.1:1502");
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(a->host, "127.0.0.1");
  EXPECT_EQ(a->port, 1502);
  const auto v6 = ParseHostPort("[::1]:65535");  // the port follows the LAST colon
  ASSERT_TRUE(v6.has_value());
  EXPECT_EQ(v6->host, "[::1]");
  EXPECT_EQ(v6->port, 65535);
}

TEST(HostPortTest, RefusesWhatIsNotHostColonPort) {
  // "1502x" and "+1502" were read as 1502 by std::stoi; an empty host or port, 0 and 65536 too.
  for (const char* text :
       {"1502", ":1502", "localhost:", "localhost:1502x", "localhost:+1502", "localhost: 1502",
        "localhost:0", "localhost:65536", "localhost:-1", "localhost:99999999999", ""}) {
    EXPECT_FALSE(ParseHostPort(text).has_value()) << "'" << text << "'";
  }
}

}  // namespace
}  // namespace hrgbench::drivers::sim
