// The panel's HTTP server under the attacks of issue 25 (rows 2, 3, 4, 7), on loopback: the panel
// runs in this process (RunPanel on a free port), the client is a raw socket so that every header
// is the test's. Sessions would run /bin/true: a test that reaches a session has already failed.
#include "app/panel/panel_server.hpp"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <string_view>
#include <thread>

#include "hrgbench/config/sha256.hpp"

namespace hrgbench::app {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

const fs::path kConfigs = fs::path(HRGBENCH_SOURCE_DIR) / "bench_configs";

fs::path FreshDir() {
  std::random_device rd;
  const fs::path dir = fs::temp_directory_path() / ("hrgbench-panel-" + std::to_string(rd()));
  fs::create_directories(dir);
  return dir;
}

int FreePort() {
  const int sock = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(sock, reinterpret_cast<sockaddr*>(&addr), sizeof(addr));
  socklen_t len = sizeof(addr);
  ::getsockname(sock, reinterpret_cast<sockaddr*>(&addr), &len);
  ::close(sock);
  return ntohs(addr.sin_port);
}

int Connect(int port) {
  const int sock = ::socket(AF_INET, SOCK_STREAM, 0);
  timeval timeout{10, 0};  // a panel that neither reads nor closes fails the test, not hangs it
  ::setsockopt(sock, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof(timeout));
  ::setsockopt(sock, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof(timeout));
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(sock, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
    ::close(sock);
    return -1;
  }
  return sock;
}

// Sends all of `bytes` or stops where the peer stops taking them; returns how much was sent.
std::size_t SendAll(int sock, std::string_view bytes) {
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n = ::send(sock, bytes.data() + sent,
                             std::min<std::size_t>(bytes.size() - sent, 64 * 1024), MSG_NOSIGNAL);
    if (n <= 0) break;
    sent += static_cast<std::size_t>(n);
  }
  return sent;
}

struct Reply {
  int status = 0;
  std::string head;
  std::string body;
};

// Reads the answer until the panel closes (every request here says Connection: close).
Reply ReadReply(int sock) {
  std::string text;
  char buf[65536];
  ssize_t n = 0;
  while ((n = ::recv(sock, buf, sizeof(buf), 0)) > 0) text.append(buf, static_cast<size_t>(n));
  Reply reply;
  const std::size_t end = text.find("\r\n\r\n");
  reply.head = text.substr(0, end);
  if (end != std::string::npos) reply.body = text.substr(end + 4);
  if (text.rfind("HTTP/1.1 ", 0) == 0) reply.status = std::atoi(text.c_str() + 9);
  return reply;
}

Reply Exchange(int port, std::string_view request) {
  const int sock = Connect(port);
  if (sock < 0) return {};
  SendAll(sock, request);
  Reply reply = ReadReply(sock);
  ::close(sock);
  return reply;
}

std::string Post(std::string_view path, std::string_view host, std::string_view origin,
                 std::string_view body) {
  std::string request = "POST " + std::string(path) + " HTTP/1.1\r\nHost: " + std::string(host) +
                        "\r\nContent-Type: application/json\r\nConnection: close\r\n";
  if (!origin.empty()) request += "Origin: " + std::string(origin) + "\r\n";
  return request + "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" +
         std::string(body);
}

std::string Get(std::string_view path, int port) {
  return "GET " + std::string(path) + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) +
         "\r\nConnection: close\r\n\r\n";
}

// A panel on the simulated station's configs, on a free loopback port, stopped at the end.
class Panel {
 public:
  explicit Panel(const fs::path& dir, int port = FreePort()) : port_(port) {
    fs::create_directories(dir / "configs");
    fs::copy_file(kConfigs / "station-sim.toml", dir / "configs" / "station.toml",
                  fs::copy_options::overwrite_existing);
    fs::copy_file(kConfigs / "sequence-production.toml", dir / "configs" / "sequence-a.toml",
                  fs::copy_options::overwrite_existing);
    options_.station = dir / "configs" / "station.toml";
    options_.listen = "127.0.0.1:" + std::to_string(port_);
    options_.sessions = dir / "sessions";
    options_.program = "/bin/true";
    thread_ = std::thread([this] { exit_code_ = RunPanel(options_, stop_); });
    for (int i = 0; i < 200 && !Ready(); ++i) std::this_thread::sleep_for(50ms);
  }
  ~Panel() {
    stop_ = 1;
    thread_.join();
  }
  bool Ready() const {
    const int sock = Connect(port_);
    if (sock >= 0) ::close(sock);
    return sock >= 0;
  }
  int port() const { return port_; }
  std::string host() const { return "127.0.0.1:" + std::to_string(port_); }
  std::string origin() const { return "http://" + host(); }
  const PanelOptions& options() const { return options_; }

 private:
  int port_;
  PanelOptions options_;
  std::atomic<int> stop_{0};
  std::atomic<int> exit_code_{-1};
  std::thread thread_;
};

bool NoSessionFolder(const fs::path& sessions) {
  return !fs::exists(sessions) || fs::is_empty(sessions);
}

// Row 2: a rebinding name that starts with "127." passed the old prefix check, and with its own
// Origin it started and aborted sessions.
TEST(PanelServer, RefusesARebindingHostOnStartAndAbort) {
  const fs::path dir = FreshDir();
  {
    Panel panel(dir);
    ASSERT_TRUE(panel.Ready());
    const std::string evil = "127.attacker.example:" + std::to_string(panel.port());
    const std::string start = R"({"serial":"SN1","sequence":0,"limits":null})";
    for (const char* path : {"/api/start", "/api/abort"}) {
      const Reply reply = Exchange(panel.port(), Post(path, evil, "http://" + evil, start));
      EXPECT_EQ(reply.status, 403) << path << ": " << reply.body;
      EXPECT_NE(reply.body.find("localhost only"), std::string::npos) << reply.body;
    }
    EXPECT_TRUE(NoSessionFolder(dir / "sessions"));
    // The real loopback name still works: past the guard, abort says no session is running.
    const Reply abort =
        Exchange(panel.port(), Post("/api/abort", panel.host(), panel.origin(), "{}"));
    EXPECT_EQ(abort.status, 409) << abort.body;
    const Reply state = Exchange(panel.port(), Get("/api/state", panel.port()));
    EXPECT_EQ(state.status, 200) << state.body;
    // A state-changing request without the token needs the panel's own Origin.
    const Reply bare = Exchange(panel.port(), Post("/api/abort", panel.host(), "", "{}"));
    EXPECT_EQ(bare.status, 403) << bare.body;
  }
  fs::remove_all(dir);
}

// Row 4: cpp-httplib's SO_REUSEPORT let a second panel bind the same port silently.
TEST(PanelServer, ASecondPanelOnTheSamePortFailsNamingThePort) {
  const fs::path dir = FreshDir();
  {
    Panel first(dir / "first");
    ASSERT_TRUE(first.Ready());
    PanelOptions options = first.options();
    options.sessions = dir / "second-sessions";
    std::atomic<int> stop{0};
    std::atomic<int> code{-1};
    testing::internal::CaptureStderr();
    std::thread second([&] { code = RunPanel(options, stop); });
    for (int i = 0; i < 100 && code == -1; ++i) std::this_thread::sleep_for(50ms);
    const bool returned = code != -1;
    stop = 1;  // a second panel that did start is stopped, so the test ends
    second.join();
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_TRUE(returned) << "the second panel started on the same port";
    EXPECT_EQ(code, 2);
    EXPECT_NE(err.find("port " + std::to_string(first.port())), std::string::npos) << err;
    EXPECT_NE(err.find("in use"), std::string::npos) << err;
  }
  fs::remove_all(dir);
}

// Row 3: cpp-httplib 0.11 applies the body limit to a Content-Length only; a chunked body of any
// size was read whole and started a session.
TEST(PanelServer, RefusesAChunkedBodyAboveTheLimit) {
  const fs::path dir = FreshDir();
  {
    Panel panel(dir);
    ASSERT_TRUE(panel.Ready());
    std::string request = "POST /api/start HTTP/1.1\r\nHost: " + panel.host() +
                          "\r\nOrigin: " + panel.origin() +
                          "\r\nContent-Type: application/json\r\nConnection: close\r\n"
                          "Transfer-Encoding: chunked\r\n\r\n";
    const std::string json = R"({"serial":"SN1","sequence":0,"limits":null})";
    request += "2b\r\n" + json + "\r\n";
    ASSERT_EQ(json.size(), 0x2bu);
    const std::string spaces(8192, ' ');
    for (int i = 0; i < 32; ++i) request += "2000\r\n" + spaces + "\r\n";  // 256 kB of padding
    request += "0\r\n\r\n";
    const Reply reply = Exchange(panel.port(), request);
    EXPECT_EQ(reply.status, 413) << reply.body;
    EXPECT_NE(reply.body.find("too large"), std::string::npos) << reply.body;
    EXPECT_TRUE(NoSessionFolder(dir / "sessions"));
    // A chunked body within the limit is read (and refused for what it says, not its size).
    const std::string small = R"({"serial":"../x","sequence":0})";
    char size[16];
    std::snprintf(size, sizeof(size), "%zx", small.size());
    const Reply ok =
        Exchange(panel.port(), "POST /api/start HTTP/1.1\r\nHost: " + panel.host() +
                                   "\r\nOrigin: " + panel.origin() +
                                   "\r\nContent-Type: application/json\r\nConnection: close\r\n"
                                   "Transfer-Encoding: chunked\r\n\r\n" +
                                   size + "\r\n" + small + "\r\n0\r\n\r\n");
    EXPECT_EQ(ok.status, 400) << ok.body;
    EXPECT_NE(ok.body.find("'/'"), std::string::npos) << ok.body;
  }
  fs::remove_all(dir);
}

// Row 3: the headers' count and total size were unbounded (12 500 headers of 8 kB got 200).
TEST(PanelServer, RefusesOversizeHeadersWithoutReadingThem) {
  const fs::path dir = FreshDir();
  {
    Panel panel(dir);
    ASSERT_TRUE(panel.Ready());
    std::string many = "GET /api/state HTTP/1.1\r\nHost: " + panel.host() + "\r\n";
    for (int i = 0; i < 1000; ++i)
      many += "X-Filler-" + std::to_string(i) + ": " + std::string(80, 'a') + "\r\n";
    many += "Connection: close\r\n\r\n";
    const Reply reply = Exchange(panel.port(), many);
    EXPECT_EQ(reply.status, 431) << reply.head << reply.body;
    EXPECT_NE(reply.body.find("too large"), std::string::npos) << reply.body;
    EXPECT_NE(reply.head.find("Connection: close"), std::string::npos) << reply.head;
    // A request line alone above the bound (cpp-httplib would give up without an answer).
    const Reply long_line = Exchange(panel.port(), "GET /api/state?" + std::string(40000, 'x') +
                                                       " HTTP/1.1\r\nHost: " + panel.host() +
                                                       "\r\nConnection: close\r\n\r\n");
    EXPECT_EQ(long_line.status, 431) << long_line.head << long_line.body;
    // 32 MB of headers: the panel stops reading long before the end and closes.
    const std::string line = "X-Bomb: " + std::string(8000, 'b') + "\r\n";
    std::string bomb = "GET /api/state HTTP/1.1\r\nHost: " + panel.host() + "\r\n";
    while (bomb.size() < (32u << 20)) bomb += line;
    bomb += "\r\n";
    const int sock = Connect(panel.port());
    ASSERT_GE(sock, 0);
    const std::size_t sent = SendAll(sock, bomb);
    const Reply bombed = ReadReply(sock);
    ::close(sock);
    EXPECT_LT(sent, bomb.size()) << "the panel read every header";
    EXPECT_NE(bombed.status, 200);
    // The panel still answers.
    EXPECT_EQ(Exchange(panel.port(), Get("/api/state", panel.port())).status, 200);
  }
  fs::remove_all(dir);
}

long PeakRssKb() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::atol(line.c_str() + 6);
  return -1;
}

// Row 3: a report was read whole into memory for every GET (and refused above 256 MB). Streamed,
// a report of 300 MB arrives intact and the panel's memory does not grow with it. The file is
// sparse (marks at a few offsets), so the test costs no disk.
TEST(PanelServer, StreamsALargeReportIntact) {
  const fs::path dir = FreshDir();
  {
    Panel panel(dir);
    ASSERT_TRUE(panel.Ready());
    const std::string name = "SN1-20260101T000000Z";
    const fs::path report = dir / "sessions" / name / "report";
    fs::create_directories(report);
    constexpr std::uintmax_t kSize = 300u << 20;
    {
      std::ofstream out(report / "report.html", std::ios::binary);
      for (std::uintmax_t at : {std::uintmax_t{0}, kSize / 3, kSize / 2, kSize - 16}) {
        out.seekp(static_cast<std::streamoff>(at));
        out << "mark@" << at;
      }
    }
    fs::resize_file(report / "report.html", kSize);
    // The expected hash, read in pieces too (the peak memory below is the process's).
    std::string expected;
    {
      config_file::Sha256 file_sha;
      std::ifstream in(report / "report.html", std::ios::binary);
      std::string piece(1 << 20, '\0');
      while (in.read(piece.data(), static_cast<std::streamsize>(piece.size())) || in.gcount() > 0)
        file_sha.Update(std::string_view(piece.data(), static_cast<std::size_t>(in.gcount())));
      expected = config_file::ToHex(file_sha.Finish());
    }

    const long before_kb = PeakRssKb();
    const int sock = Connect(panel.port());
    ASSERT_GE(sock, 0);
    SendAll(sock, Get("/sessions/" + name + "/report/report.html", panel.port()));
    // Hashed as it arrives: the test keeps no copy either.
    std::string head;
    config_file::Sha256 sha;
    std::uintmax_t body_bytes = 0;
    char buf[65536];
    ssize_t n = 0;
    while ((n = ::recv(sock, buf, sizeof(buf), 0)) > 0) {
      std::string_view chunk(buf, static_cast<std::size_t>(n));
      if (head.find("\r\n\r\n") == std::string::npos) {
        head.append(chunk);
        const std::size_t end = head.find("\r\n\r\n");
        if (end == std::string::npos) continue;
        chunk = std::string_view(head).substr(end + 4);
      }
      sha.Update(chunk);
      body_bytes += chunk.size();
    }
    ::close(sock);
    EXPECT_EQ(head.rfind("HTTP/1.1 200", 0), 0u) << head.substr(0, 200);
    EXPECT_EQ(body_bytes, kSize);
    EXPECT_EQ(config_file::ToHex(sha.Finish()), expected);
    const long grown_kb = PeakRssKb() - before_kb;
    EXPECT_LT(grown_kb, 64 * 1024) << "the panel's peak memory grew by " << grown_kb << " kB";
  }
  fs::remove_all(dir);
}

// Row 7: a link in a session's folder was followed out of the sessions folder.
TEST(PanelServer, RefusesAReportLinkOutOfTheSessionsFolder) {
  const fs::path dir = FreshDir();
  {
    Panel panel(dir);
    ASSERT_TRUE(panel.Ready());
    const fs::path sessions = dir / "sessions";
    fs::create_directories(sessions / "SN1-20260101T000000Z" / "report");
    std::ofstream(sessions / "SN1-20260101T000000Z" / "report" / "report.html") << "<p>ok</p>";
    fs::create_symlink("/etc/passwd", sessions / "SN1-20260101T000000Z" / "report" / "leak.html");
    fs::create_directories(sessions / "SN2-20260101T000000Z");
    fs::create_directory_symlink("/etc", sessions / "SN2-20260101T000000Z" / "report");
    // A link that stays inside the report folder is served.
    fs::create_symlink("report.html", sessions / "SN1-20260101T000000Z" / "report" / "index.html");

    const auto get = [&](const std::string& path) {
      return Exchange(panel.port(), Get(path, panel.port()));
    };
    const Reply ok = get("/sessions/SN1-20260101T000000Z/report/report.html");
    EXPECT_EQ(ok.status, 200);
    EXPECT_EQ(ok.body, "<p>ok</p>");
    EXPECT_EQ(get("/sessions/SN1-20260101T000000Z/report/index.html").body, "<p>ok</p>");
    const Reply leak = get("/sessions/SN1-20260101T000000Z/report/leak.html");
    EXPECT_EQ(leak.status, 404) << leak.body.substr(0, 200);
    EXPECT_EQ(leak.body.find("root:"), std::string::npos);
    const Reply folder = get("/sessions/SN2-20260101T000000Z/report/passwd");
    EXPECT_EQ(folder.status, 404) << folder.body.substr(0, 200);
    EXPECT_EQ(folder.body.find("root:"), std::string::npos);
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hrgbench::app
