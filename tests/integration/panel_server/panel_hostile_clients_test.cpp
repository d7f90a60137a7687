// Issue 25 row 1: clients that hold the panel's connections (event streams that never read,
// heads sent slowly) must not delay the operator's Abort. The panel runs a real session
// (hrg-bench on the simulated station at real time) so that the Abort has something to stop;
// every client is on loopback, their number and the test's time are bounded.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "panel_session_support.hpp"

namespace hrgbench::app {
namespace {

namespace fs = std::filesystem;
using namespace hrgbench::testing::panel;
using namespace std::chrono_literals;

constexpr int kHostileStreams = 40;
constexpr int kHostileHeads = 40;

// A client that asks for the event stream and never reads it (a small receive buffer, so that
// it is full after a few events).
int StreamThatDoesNotRead(int port) {
  const int sock = ::socket(AF_INET, SOCK_STREAM, 0);
  const int small = 4096;
  ::setsockopt(sock, SOL_SOCKET, SO_RCVBUF, &small, sizeof small);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(sock, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(sock);
    return -1;
  }
  SendAll(sock, "GET /api/events HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\n\r\n");
  return sock;
}

// A client that sends the start of a head and then nothing.
int SlowHead(int port) {
  const int sock = Connect(port);
  if (sock >= 0) SendAll(sock, "GET /api/state HTTP/1.1\r\nHost: 127.0.0.1:");
  return sock;
}

TEST(PanelHostileClients, AnAbortGetsThroughStreamsThatDoNotReadAndSlowHeads) {
  const fs::path dir = FreshDir();
  {
    Panel panel(dir, FreePort(), kBench, RealTimeStation(dir / "station"));
    ASSERT_TRUE(panel.Ready());
    const Reply started =
        Exchange(panel.port(),
                 Post("/api/start", panel.host(), panel.origin(),
                      R"({"serial":"SN-HOSTILE","sequence":0,"limits":null,"operator":"OP-T"})"));
    ASSERT_EQ(started.status, 200) << started.body;
    const std::string name = Json(started.body).value("session", "");
    ASSERT_FALSE(name.empty()) << started.body;

    std::vector<int> streams;
    std::vector<int> heads;
    for (int i = 0; i < kHostileStreams; ++i)
      streams.push_back(StreamThatDoesNotRead(panel.port()));
    for (int i = 0; i < kHostileHeads; ++i) heads.push_back(SlowHead(panel.port()));
    std::this_thread::sleep_for(200ms);  // every hostile request has reached the panel

    // The Abort: answered while every hostile client still holds its connection. Connect's
    // receive timeout (10 s) is the hang guard: before the gate, the answer came after 27 s.
    const int sock = Connect(panel.port());
    ASSERT_GE(sock, 0);
    SendAll(sock, Post("/api/abort", panel.host(), panel.origin(), "{}"));
    const Reply abort = ReadReply(sock);
    ::close(sock);
    ASSERT_EQ(abort.status, 200) << "no answer to the Abort: " << abort.head << abort.body;
    EXPECT_EQ(abort.body, R"({"aborting":true})");

    // The session stops safely and its record says why (hang guard: 60 s).
    const nlohmann::json session = WaitForSessionEnd(panel, 60s);
    ASSERT_TRUE(session.is_object()) << "the panel's state did not answer";
    EXPECT_FALSE(session.value("running", true)) << session.dump();
    const nlohmann::json record = ReadRecord(dir / "sessions" / name);
    ASSERT_TRUE(record.is_object()) << "no record in " << name;
    EXPECT_EQ(record["outcome"]["kind"], "ABORTED") << record["outcome"].dump();
    const std::string reason = record["outcome"].value("reason", "");
    EXPECT_EQ(reason.rfind("aborted by operator", 0), 0u) << reason;

    // The slow heads were dropped (408, closed, or reset when the panel closed one with bytes
    // unread), not left to hold the panel (guard: Connect's 10 s each).
    for (int head : heads) {
      char byte = 0;
      const ssize_t n = ::recv(head, &byte, 1, 0);
      EXPECT_TRUE(n >= 0 || errno == ECONNRESET) << "a slow head is still open";
      ::close(head);
    }
    for (int stream : streams) ::close(stream);
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hrgbench::app
