#pragma once
// The panel's HTTP server: Debian's cpp-httplib (0.11) with bounds on what a client can make it
// read and a listening socket of its own (issue 25 rows 3 and 4).
//
// cpp-httplib 0.11 reads a request's line and headers without a total bound (only each line is
// limited, to 8 kB, after the line has been read whole; the count is unbounded) and bounds a
// body only when it has a Content-Length (a chunked or unframed body is read whole). Its library
// is compiled, so its limits cannot be changed by macros here. BoundedServer therefore serves
// each connection through a stream of its own that counts what it hands to cpp-httplib: the
// request line and headers together at most RequestBounds::head_bytes, the raw bytes after them
// at most RequestBounds::body_bytes. A request past a bound is answered 431 (head) or 413 (body)
// and its connection closed; the rest of what the client sends is not read (beyond a short,
// bounded drain so that the client gets the answer instead of a reset).
//
// Any refusal (a status >= 400, see CloseConnectionAfterResponse) closes its connection too, so
// that the unread rest of a refused request is never taken for the next one.
//
// Connections are accepted, admitted and read up to a complete request by the gate
// (panel_gate.hpp), which hands each complete request to ServeOne on a worker and takes the
// connection back after the response (keep-alive) or closes it.
//
// Threads: ServeOne serves one request on the calling (worker) thread; the functions below that
// name "the current request" must be called on that thread (from a handler, the pre-routing or
// the error handler).
//
// Last include of its users: <httplib.h> brings <resolv.h>, whose `_res` macro breaks Eigen.

#include <httplib.h>  // NOLINT(llvm-include-order)

#include <chrono>
#include <cstddef>
#include <string>

namespace hrgbench::app {

struct RequestBounds {
  // The request line and every header together. Browsers send 1-2 kB; cookies set on "localhost"
  // by other programs on the machine are sent to every port and can reach a few kB.
  std::size_t head_bytes = 32 * 1024;
  // The raw bytes after the head, chunk framing included: a backstop above any accepted body.
  std::size_t body_bytes = 128 * 1024;
};

enum class BoundHit { kNone, kHead, kBody };

// What becomes of a connection after ServeOne.
struct Served {
  enum class Next {
    kKeep,   // keep-alive: back to the gate for its next request, with `unread` bytes of it
    kClose,  // closed (the client asked, or the exchange failed)
    kDrain,  // refused: no more writes, read and drop what the client still sends, then close
  };
  Next next = Next::kKeep;
  std::string unread;
};

class BoundedServer : public httplib::Server {
 public:
  explicit BoundedServer(RequestBounds bounds);

  // bind_to_port, then the backlog raised to `backlog` and the socket made non-blocking (the gate
  // accepts until there is nothing left). False when the port cannot be bound.
  bool Bind(const std::string& host, int port, int backlog);
  int ListenSocket() const;
  const RequestBounds& bounds() const { return bounds_; }
  void CloseListenSocket();  // any thread; providers of a running response then stop

  // Serves the one request whose first bytes (`buffered`, read by the gate) are given; the rest
  // of it, if any, must arrive by `read_deadline`. Writes fail after the write timeout.
  Served ServeOne(int sock, std::string buffered,
                  std::chrono::steady_clock::time_point read_deadline);

  // Which bound the current request went past (kNone outside a request's thread).
  static BoundHit CurrentRequestHit();
  // Closes the current request's connection once its response is written.
  static void CloseConnectionAfterResponse();

 private:
  RequestBounds bounds_;
};

// Socket options for the listening socket: SO_REUSEADDR only (a restarted panel binds while old
// connections are in TIME_WAIT). cpp-httplib's default sets SO_REUSEPORT, with which a second
// panel binds the same port silently and the kernel shares the connections between the two (an
// Abort then reaches the wrong one); without it the second bind fails.
void ExclusiveListenSocket(socket_t sock);

}  // namespace hrgbench::app
