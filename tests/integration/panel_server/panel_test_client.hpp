#pragma once
// The panel's HTTP server seen from a raw socket on loopback, for the panel's integration tests:
// the panel runs in the test's process (RunPanel on a free port), every header is the test's.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <thread>

#include "app/panel/panel_server.hpp"

namespace hrgbench::testing::panel {

namespace fs = std::filesystem;
using app::PanelOptions;
using app::RunPanel;
using namespace std::chrono_literals;

inline const fs::path kConfigs = fs::path(HRGBENCH_SOURCE_DIR) / "bench_configs";

inline fs::path FreshDir() {
  std::random_device rd;
  const fs::path dir = fs::temp_directory_path() / ("hrgbench-panel-" + std::to_string(rd()));
  fs::create_directories(dir);
  return dir;
}

inline int FreePort() {
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

inline int Connect(int port) {
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
inline std::size_t SendAll(int sock, std::string_view bytes) {
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
inline Reply ReadReply(int sock) {
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

inline Reply Exchange(int port, std::string_view request) {
  const int sock = Connect(port);
  if (sock < 0) return {};
  SendAll(sock, request);
  Reply reply = ReadReply(sock);
  ::close(sock);
  return reply;
}

inline std::string Post(std::string_view path, std::string_view host, std::string_view origin,
                        std::string_view body) {
  std::string request = "POST " + std::string(path) + " HTTP/1.1\r\nHost: " + std::string(host) +
                        "\r\nContent-Type: application/json\r\nConnection: close\r\n";
  if (!origin.empty()) request += "Origin: " + std::string(origin) + "\r\n";
  return request + "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" +
         std::string(body);
}

inline std::string Get(std::string_view path, int port) {
  return "GET " + std::string(path) + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) +
         "\r\nConnection: close\r\n\r\n";
}

// The panel's sessions leave their reports to jobs (hrg-bench --report background) that outlive
// the panel: a test's folder is removed only once none of them still writes into it.
inline void WaitForReportJobs(const fs::path& sessions) {
  std::error_code ec;
  if (!fs::is_directory(sessions, ec)) return;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  for (auto it = fs::recursive_directory_iterator(sessions, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (it->path().filename() != "job.json") continue;
    std::ifstream in(it->path());
    std::stringstream text;
    text << in.rdbuf();
    const std::string json = text.str();
    const std::size_t at = json.find("\"pid\":");
    if (at == std::string::npos || json.find("\"running\"") == std::string::npos) continue;
    const long pid = std::atol(json.c_str() + at + 6);
    while (pid > 0 && fs::exists("/proc/" + std::to_string(pid)) &&
           std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(50ms);
  }
}

// A panel on the simulated station's configs, on a free loopback port, stopped at the end.
class Panel {
 public:
  // `program`: what a session runs (/bin/true: a test that reaches a session has already
  // failed); `station`: the station file copied in (the simulated station by default); `sequence`:
  // the one sequence offered (id 0).
  explicit Panel(const fs::path& dir, int port = FreePort(), const fs::path& program = "/bin/true",
                 const fs::path& station = kConfigs / "station-sim.toml",
                 const fs::path& sequence = kConfigs / "sequence-production.toml")
      : port_(port) {
    fs::create_directories(dir / "configs");
    {
      // Without the shipped [offers] (it names files beside the shipped station): this panel
      // offers the one sequence copied beside it.
      std::ifstream in(station);
      std::stringstream text;
      text << in.rdbuf();
      std::string toml = text.str();
      toml = toml.substr(0, toml.find("\n[offers]"));
      std::ofstream(dir / "configs" / "station.toml") << toml << '\n';
    }
    {
      // Without the sequence's [[prompts]] (the production sequence's operator steps): these
      // sessions have nobody at the dialog. The prompts are the browser test's (fixture case).
      std::ifstream in(sequence);
      std::stringstream text;
      text << in.rdbuf();
      std::string toml = text.str();
      toml = toml.substr(0, toml.find("\n[[prompts]]"));
      std::ofstream(dir / "configs" / "sequence-a.toml") << toml << '\n';
    }
    options_.station = dir / "configs" / "station.toml";
    options_.listen = "127.0.0.1:" + std::to_string(port_);
    options_.sessions = dir / "sessions";
    options_.program = program;
    thread_ = std::thread([this] { exit_code_ = RunPanel(options_, stop_); });
    for (int i = 0; i < 200 && !Ready(); ++i) std::this_thread::sleep_for(50ms);
  }
  ~Panel() {
    stop_ = 1;
    thread_.join();
    WaitForReportJobs(options_.sessions);
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

inline bool NoSessionFolder(const fs::path& sessions) {
  return !fs::exists(sessions) || fs::is_empty(sessions);
}

}  // namespace hrgbench::testing::panel
