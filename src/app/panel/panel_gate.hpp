#pragma once
// The panel's front door (issue 25 row 1: "Abort always gets through"). cpp-httplib gives every
// connection a pool thread from its first byte to its close, so 40 event streams that never read,
// or 40 clients that send their headers slowly, held all 32 threads and an Abort waited 27 s.
//
// The gate instead holds every connection that has no complete request yet (a new one, a slow
// one, a keep-alive one between requests) in one poll() loop on its own thread, where it costs a
// descriptor and a buffer, never a thread:
//   - admission: at most GateLimits::max_connections in all and max_per_address from one client
//     address. A new connection over a bound takes the place of the oldest one the gate holds
//     (from that address when the address is over its bound) that has no complete request: a
//     client that is slow to ask loses its place to one that asks now. When there is none, the
//     new connection is answered 503 (Connection: close) at once, without reading it.
//   - deadlines: a request's head (and a body with a Content-Length of at most body_wait_bytes)
//     must be complete head_timeout after its first byte (else 408 and closed); a connection
//     with no request is closed after idle_timeout.
//   - only GET, POST and HEAD: any other method is answered 405 at once (a PUT with a body
//     held a worker for the read timeout).
//   - a complete request goes to its lane's own pool (Lane): Abort on threads of its own, start
//     and state on the control threads, event streams on at most max_streams threads (a stream
//     over the bound is answered 503), everything else (the page, reports) on the general pool.
//     No lane can take another's threads, so the control path never waits behind a stream, a
//     report or a slow client.
// After the response the worker gives the connection back (keep-alive) or the gate closes it;
// a refused request's connection is drained (read and dropped, at most 1 MB or 1 s) so that its
// client reads the answer instead of a reset.
//
// Threads: Serve runs the gate on the caller's thread until Stop (any thread); the lanes' pools
// are joined before Serve returns (an event stream ends at its next keep-alive, 5 s at most).

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

namespace hrgbench::app {

class BoundedServer;

enum class Lane { kGeneral, kStream, kControl, kAbort };

struct GateLimits {
  // Open connections in all; each costs a descriptor (the process has 1024) and its buffer.
  std::size_t max_connections = 256;
  // From one client address. A browser opens up to 6 per host plus its event stream.
  std::size_t max_per_address = 32;
  // Event streams at once: every open page holds one; far fewer than the general pool's threads.
  std::size_t max_streams = 8;
  std::size_t general_threads = 16;
  std::size_t control_threads = 2;  // start and state (state may query the results store)
  std::size_t abort_threads = 2;    // Abort alone: answered without reading anything more
  // A request's head must be complete this long after its first byte ("a few seconds": a slow
  // client loses its connection, a browser on a slow link still gets through).
  std::chrono::milliseconds head_timeout{3000};
  std::chrono::milliseconds idle_timeout{5000};  // keep-alive between requests
  // A body with a Content-Length up to this is read by the gate before the request goes to its
  // lane, so Abort's threads never wait for a client's bytes.
  std::size_t body_wait_bytes = 64 * 1024;
  int backlog = 128;
};

class PanelGate {
 public:
  using Classify = std::function<Lane(std::string_view method, std::string_view path)>;

  // `server` must have been bound (BoundedServer::Bind) and routed; it outlives the gate.
  PanelGate(BoundedServer& server, GateLimits limits, Classify classify);
  ~PanelGate();
  PanelGate(const PanelGate&) = delete;
  PanelGate& operator=(const PanelGate&) = delete;

  void Serve();
  void Stop();

 private:
  struct Handback {  // a connection a worker is done with
    int fd;
    bool keep;  // false: drain (refused) or close
    bool drain;
    std::string unread;  // keep-alive: what the client already sent of its next request
    Lane lane;
  };
  void GiveBack(Handback handback);

  BoundedServer& server_;
  GateLimits limits_;
  Classify classify_;
  int wake_;  // an eventfd: Stop and a worker's returned connection end the poll
  std::atomic<bool> stop_{false};
  std::mutex handback_mutex_;
  std::vector<Handback> handbacks_;
};

}  // namespace hrgbench::app
