// The panel's HTTP server under the attacks of issue 25 (rows 2, 3, 4, 7), on loopback: the panel
// runs in this process (RunPanel on a free port), the client is a raw socket so that every header
// is the test's. Sessions would run /bin/true: a test that reaches a session has already failed.
#include <gtest/gtest.h>
#include <linux/inet_diag.h>
#include <linux/netlink.h>
#include <linux/sock_diag.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "hrgbench/config/sha256.hpp"
#include "panel_test_client.hpp"

namespace hrgbench::app {
namespace {

namespace fs = std::filesystem;
using namespace hrgbench::testing::panel;
using namespace std::chrono_literals;

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
    ::testing::internal::CaptureStderr();
    std::thread second([&] { code = RunPanel(options, stop); });
    for (int i = 0; i < 100 && code == -1; ++i) std::this_thread::sleep_for(50ms);
    const bool returned = code != -1;
    stop = 1;  // a second panel that did start is stopped, so the test ends
    second.join();
    const std::string err = ::testing::internal::GetCapturedStderr();
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

// Issue 27 §4: the panel's sessions leave their report to a job (--report background). Its link,
// opened before the job is done, answers 202 and reloads; a job that failed or was killed says
// why and how to make the report. The records are written as the docs give them, by hand.
TEST(PanelServer, AReportStillBeingWrittenAnswers202AndAFailedOneSaysWhy) {
  const fs::path dir = FreshDir();
  pid_t job = 0;
  {
    Panel panel(dir);
    ASSERT_TRUE(panel.Ready());
    const fs::path sessions = dir / "sessions";
    const auto record = [&](const std::string& name, const std::string& state, pid_t pid,
                            const std::string& reason) {
      fs::create_directories(sessions / name / "report");
      std::ofstream(sessions / name / "report" / "job.json")
          << "{\"format\": \"hrgbench-report-job\", \"version\": 1, \"state\": \"" << state
          << "\", \"pid\": " << pid << ", \"started\": \"2026-11-27T10:00:00Z\", \"reason\": "
          << (reason.empty() ? "null" : "\"" + reason + "\"") << "}";
    };
    // A live job: a process whose program is named hrg-report (a link to sleep).
    fs::create_symlink("/bin/sleep", dir / "hrg-report");
    job = ::fork();
    if (job == 0) {
      ::execl((dir / "hrg-report").c_str(), (dir / "hrg-report").c_str(), "60", nullptr);
      ::_exit(127);
    }
    ASSERT_GT(job, 0);
    for (int i = 0; i < 200; ++i) {
      std::ifstream in("/proc/" + std::to_string(job) + "/cmdline");
      std::string argv0;
      if (std::getline(in, argv0, '\0') && fs::path(argv0).filename() == "hrg-report") break;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    record("SN1-20260101T000000Z", "running", job, "");
    record("SN2-20260101T000000Z", "running", 999999999, "");  // no such process: killed
    record("SN3-20260101T000000Z", "failed", 1, "session.json: outcome: missing");
    const auto get = [&](const std::string& name) {
      return Exchange(panel.port(), Get("/sessions/" + name + "/report/report.html", panel.port()));
    };
    const Reply running = get("SN1-20260101T000000Z");
    EXPECT_EQ(running.status, 202) << running.head << running.body;
    EXPECT_NE(running.head.find("Retry-After: 2"), std::string::npos) << running.head;
    EXPECT_NE(running.body.find("http-equiv=\"refresh\""), std::string::npos) << running.body;
    EXPECT_NE(running.body.find("being written (job " + std::to_string(job)), std::string::npos)
        << running.body;
    const Reply killed = get("SN2-20260101T000000Z");
    EXPECT_EQ(killed.status, 404) << killed.body;
    EXPECT_NE(killed.body.find("interrupted"), std::string::npos) << killed.body;
    EXPECT_NE(killed.body.find("hrg-report"), std::string::npos) << killed.body;
    const Reply failed = get("SN3-20260101T000000Z");
    EXPECT_EQ(failed.status, 404) << failed.body;
    EXPECT_NE(failed.body.find("outcome: missing"), std::string::npos) << failed.body;
    // Another file of a report being written is simply not there yet.
    EXPECT_EQ(Exchange(panel.port(),
                       Get("/sessions/SN1-20260101T000000Z/report/report.pdf", panel.port()))
                  .status,
              404);
    // Gone before the panel's end, which waits for its sessions' running report jobs.
    ::kill(job, SIGKILL);
    int status = 0;
    ::waitpid(job, &status, 0);
  }
  fs::remove_all(dir);
}

// Row 14: a PUT (or PATCH) with a Content-Length held a worker until its read timed out (5 s)
// and was then answered 400; another method is refused 405 at once, naming the allowed ones.
TEST(PanelServer, AnotherMethodIsRefused405AtOnce) {
  const fs::path dir = FreshDir();
  {
    Panel panel(dir);
    ASSERT_TRUE(panel.Ready());
    for (const char* method : {"PUT", "PATCH", "DELETE", "OPTIONS"}) {
      const Reply reply = Exchange(
          panel.port(), std::string(method) + " /api/abort HTTP/1.1\r\nHost: " + panel.host() +
                            "\r\nContent-Type: application/json\r\nContent-Length: 100\r\n\r\n");
      EXPECT_EQ(reply.status, 405) << method << ": " << reply.head << reply.body;
      EXPECT_NE(reply.head.find("Allow: GET, POST, HEAD"), std::string::npos) << reply.head;
      EXPECT_NE(reply.head.find("Connection: close"), std::string::npos) << reply.head;
    }
  }
  fs::remove_all(dir);
}

// The listening socket's backlog as the kernel holds it (sock_diag: a listening socket's
// idiag_wqueue is its backlog), or -1 when it cannot be read.
int ListenBacklog(int port) {
  const int nl = ::socket(AF_NETLINK, SOCK_DGRAM | SOCK_CLOEXEC, NETLINK_SOCK_DIAG);
  if (nl < 0) return -1;
  struct {
    nlmsghdr header;
    inet_diag_req_v2 request;
  } message{};
  message.header.nlmsg_len = sizeof message;
  message.header.nlmsg_type = SOCK_DIAG_BY_FAMILY;
  message.header.nlmsg_flags = NLM_F_REQUEST | NLM_F_DUMP;
  message.request.sdiag_family = AF_INET;
  message.request.sdiag_protocol = IPPROTO_TCP;
  message.request.idiag_states = 1u << 10;  // TCP_LISTEN
  sockaddr_nl kernel{};
  kernel.nl_family = AF_NETLINK;
  int backlog = -1;
  if (::sendto(nl, &message, sizeof message, 0, reinterpret_cast<sockaddr*>(&kernel),
               sizeof kernel) > 0) {
    alignas(nlmsghdr) char buffer[32768];
    bool done = false;
    while (!done) {
      const ssize_t n = ::recv(nl, buffer, sizeof buffer, 0);
      if (n <= 0) break;
      // The messages one after another, each at a 4-byte boundary (NLMSG_NEXT without its casts).
      const auto size = static_cast<std::size_t>(n);
      for (std::size_t at = 0; at + sizeof(nlmsghdr) <= size;) {
        nlmsghdr h{};
        std::memcpy(&h, buffer + at, sizeof h);
        if (h.nlmsg_len < sizeof h || at + h.nlmsg_len > size) break;
        if (h.nlmsg_type == NLMSG_DONE || h.nlmsg_type == NLMSG_ERROR) {
          done = true;
          break;
        }
        inet_diag_msg diag{};
        std::memcpy(&diag, buffer + at + ((sizeof h + 3) & ~std::size_t{3}), sizeof diag);
        if (ntohs(diag.id.idiag_sport) == port) backlog = static_cast<int>(diag.idiag_wqueue);
        at += (h.nlmsg_len + 3) & ~std::uint32_t{3};
      }
    }
  }
  ::close(nl);
  return backlog;
}

// Row 14: cpp-httplib listens with a backlog of 5 (compiled into Debian's library), so a burst
// of connections beyond it waited for SYN retries.
TEST(PanelServer, ListensWithABacklogAboveFive) {
  const fs::path dir = FreshDir();
  {
    Panel panel(dir);
    ASSERT_TRUE(panel.Ready());
    const int backlog = ListenBacklog(panel.port());
    ASSERT_GE(backlog, 0) << "sock_diag did not list the panel's socket";
    EXPECT_GE(backlog, 128);
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hrgbench::app
