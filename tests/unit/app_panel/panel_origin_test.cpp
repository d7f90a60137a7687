// Who may talk to the panel without its token (issue 25 row 2): a Host that names the panel
// exactly, never by a prefix (the rebinding name "127.attacker.example" passed a prefix check), a
// connection from a loopback address, and an Origin equal to the accepted Host.
#include "app/panel/panel_origin.hpp"

#include <gtest/gtest.h>

namespace hrgbench::app {
namespace {

TEST(PanelOrigin, ParsesHostAndPort) {
  auto v4 = ParseHostHeader("127.0.0.1:8080");
  ASSERT_TRUE(v4);
  EXPECT_EQ(v4->host, "127.0.0.1");
  EXPECT_EQ(v4->port, 8080);
  auto v6 = ParseHostHeader("[::1]:80");
  ASSERT_TRUE(v6);
  EXPECT_EQ(v6->host, "[::1]");
  EXPECT_EQ(v6->port, 80);
  auto bare = ParseHostHeader("localhost");
  ASSERT_TRUE(bare);
  EXPECT_EQ(bare->port, std::nullopt);
  for (const char* bad : {"", ":8080", "localhost:", "localhost:80x", "localhost:0",
                          "localhost:65536", "[::1", "[::1]x", "a:1:2", "localhost:+80"})
    EXPECT_FALSE(ParseHostHeader(bad)) << bad;
}

TEST(PanelOrigin, AcceptsOnlyThePanelsExactName) {
  for (const char* good : {"127.0.0.1:8080", "localhost:8080", "LocalHost:8080", "[::1]:8080"})
    EXPECT_TRUE(IsPanelHost(good, "127.0.0.1", 8080)) << good;
  for (const char* bad :
       {"127.attacker.example:8080", "127.0.0.1.attacker.example:8080", "localhost.example:8080",
        "127.0.0.1:8081", "127.0.0.1", "127.0.0.1:8080x", "evil.example:8080", "",
        "127.0.0.1:8080:8080", "localhost:08080x"})
    EXPECT_FALSE(IsPanelHost(bad, "127.0.0.1", 8080)) << bad;
  EXPECT_TRUE(IsPanelHost("localhost", "127.0.0.1", 80));  // browsers omit HTTP's default port
  EXPECT_TRUE(IsPanelHost("127.0.0.2:9000", "127.0.0.2", 9000));   // the loopback it listens on
  EXPECT_FALSE(IsPanelHost("10.0.0.5:9000", "10.0.0.5", 9000));    // not loopback: token only
  EXPECT_FALSE(IsPanelHost("127.0.0.2:9000", "127.0.0.1", 9000));  // another loopback name
}

TEST(PanelOrigin, LoopbackIsDecidedOnTheAddressItself) {
  for (const char* good : {"127.0.0.1", "127.1.2.3", "::1", "::ffff:127.0.0.1"})
    EXPECT_TRUE(IsLoopbackAddress(good)) << good;
  for (const char* bad :
       {"127.attacker.example", "127.0.0.1.example", "10.0.0.1", "::ffff:10.0.0.1", "", "127.0.0",
        "127.0.0.256", "127.0.0.1 ", "::2", "localhost"})
    EXPECT_FALSE(IsLoopbackAddress(bad)) << bad;
}

TEST(PanelOrigin, OriginMustBeThePanelsOwn) {
  EXPECT_TRUE(IsPanelOrigin("http://127.0.0.1:8080", "127.0.0.1:8080"));
  EXPECT_TRUE(IsPanelOrigin("http://LOCALHOST:8080", "localhost:8080"));
  EXPECT_FALSE(IsPanelOrigin("http://127.0.0.1:8081", "127.0.0.1:8080"));
  EXPECT_FALSE(IsPanelOrigin("https://127.0.0.1:8080", "127.0.0.1:8080"));
  EXPECT_FALSE(IsPanelOrigin("null", "127.0.0.1:8080"));
  EXPECT_FALSE(IsPanelOrigin("", "127.0.0.1:8080"));
  EXPECT_FALSE(IsPanelOrigin("http://127.0.0.1:8080/", "127.0.0.1:8080"));
}

}  // namespace
}  // namespace hrgbench::app
