// The operator panel's Abort under hostile clients (issue 25 row 1; goal: < 200 ms): a panel in
// this process on a free loopback port, 40 clients that open the event stream and never read it
// and 40 that send the start of a head and then nothing (the slow heads are opened again before
// every try, since the panel drops them after its head timeout), then POST /api/abort, timed from
// connect() to the end of its answer (Connection: close). Prints the median and maximum over the
// tries, and how the Abort was answered.
//
//   panel_abort_latency [TRIES] [HRG-BENCH]
// Without HRG-BENCH the panel's sessions run /bin/true: no session is running and each Abort is
// answered 409 on the same path (gate, Abort's lane, the guard, the session's lock). With it,
// each try starts a real session (the simulated station at real time), aborts it 0.3 s later and
// waits for it to end: 200 {"aborting":true}.
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "panel_session_support.hpp"

namespace {

using namespace hrgbench::testing::panel;
using Clock = std::chrono::steady_clock;

constexpr int kStreams = 40;
constexpr int kHeads = 40;

int StreamThatDoesNotRead(int port) {
  const int sock = Connect(port);
  if (sock >= 0)
    SendAll(sock,
            "GET /api/events HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\n\r\n");
  return sock;
}

int SlowHead(int port) {
  const int sock = Connect(port);
  if (sock >= 0) SendAll(sock, "GET /api/state HTTP/1.1\r\nHost: 127.0.0.1:");
  return sock;
}

}  // namespace

int main(int argc, char** argv) {
  const int tries = argc > 1 ? std::atoi(argv[1]) : 50;
  const bool real = argc > 2;
  const fs::path dir = FreshDir();
  std::vector<double> ms;
  std::map<int, int> statuses;
  {
    const fs::path program = real ? fs::path(argv[2]) : fs::path("/bin/true");
    Panel panel(dir, FreePort(), program, RealTimeStation(dir / "station"));
    if (!panel.Ready()) {
      std::fprintf(stderr, "the panel did not start\n");
      return 1;
    }
    std::vector<int> streams;
    for (int i = 0; i < kStreams; ++i) streams.push_back(StreamThatDoesNotRead(panel.port()));
    std::vector<int> heads;
    for (int t = 0; t < tries; ++t) {
      for (int head : heads) ::close(head);
      heads.clear();
      for (int i = 0; i < kHeads; ++i) heads.push_back(SlowHead(panel.port()));
      if (real) {
        const Reply started =
            Exchange(panel.port(), Post("/api/start", panel.host(), panel.origin(),
                                        R"({"serial":"SN-BENCH","sequence":0,"limits":null})"));
        if (started.status != 200) {
          std::fprintf(stderr, "start: %d %s\n", started.status, started.body.c_str());
          return 1;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
      } else {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      const auto begin = Clock::now();
      const int sock = Connect(panel.port());
      SendAll(sock, Post("/api/abort", panel.host(), panel.origin(), "{}"));
      const Reply abort = ReadReply(sock);
      const auto end = Clock::now();
      ::close(sock);
      ms.push_back(std::chrono::duration<double, std::milli>(end - begin).count());
      ++statuses[abort.status];
      if (real) WaitForSessionEnd(panel, std::chrono::seconds(120));
    }
    for (int head : heads) ::close(head);
    for (int stream : streams) ::close(stream);
  }
  fs::remove_all(dir);
  std::sort(ms.begin(), ms.end());
  std::printf("Abort under %d streams that do not read + %d slow heads, %d tries (%s)\n", kStreams,
              kHeads, tries, real ? "real sessions" : "no session: 409");
  std::printf("median %.2f ms, max %.2f ms, min %.2f ms\n", ms[ms.size() / 2], ms.back(),
              ms.front());
  for (const auto& [status, count] : statuses) std::printf("  status %d: %d\n", status, count);
  return 0;
}
