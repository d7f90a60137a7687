#include "app/panel/panel_http.hpp"

#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <string>

namespace hrgbench::app {
namespace {

using Clock = std::chrono::steady_clock;

constexpr std::size_t kReadBufferBytes = 4096;

int ToMs(time_t sec, time_t usec) { return static_cast<int>(sec * 1000 + usec / 1000); }

// Waits up to `timeout_ms` for `events`; false on a timeout or an error.
bool Poll(int fd, short events, int timeout_ms) {
  pollfd p{fd, events, 0};
  int n = 0;
  do {
    n = ::poll(&p, 1, timeout_ms);
  } while (n < 0 && errno == EINTR);
  return n > 0 && (p.revents & (events | POLLHUP | POLLERR)) != 0;
}

void AddressOf(const sockaddr_storage& addr, socklen_t len, std::string& ip, int& port) {
  std::array<char, NI_MAXHOST> host{};
  std::array<char, NI_MAXSERV> serv{};
  if (::getnameinfo(reinterpret_cast<const sockaddr*>(&addr), len, host.data(), host.size(),
                    serv.data(), serv.size(), NI_NUMERICHOST | NI_NUMERICSERV) == 0) {
    ip = host.data();
    port = std::atoi(serv.data());
  }
}

// One connection's socket, counting what cpp-httplib reads of each request (see the header).
// Starts with the bytes the gate has already read of the request (panel_gate.hpp).
class BoundedStream final : public httplib::Stream {
 public:
  BoundedStream(int sock, const RequestBounds& bounds, std::string buffered,
                Clock::time_point read_deadline, int read_timeout_ms, int write_timeout_ms)
      : sock_(sock),
        bounds_(bounds),
        buffer_(std::move(buffered)),
        read_deadline_(read_deadline),
        read_timeout_ms_(read_timeout_ms),
        write_timeout_ms_(write_timeout_ms) {}

  bool Buffered() const { return off_ < buffer_.size(); }
  std::string Unread() const { return buffer_.substr(off_); }
  BoundHit Hit() const { return hit_; }
  void CloseAfterResponse() { close_ = true; }
  bool Closing() const { return close_ || hit_ != BoundHit::kNone; }

  bool is_readable() const override { return Buffered() || Poll(sock_, POLLIN, ReadWaitMs()); }
  bool is_writable() const override {
    return Poll(sock_, POLLOUT, write_timeout_ms_) && PeerStillThere();
  }

  ssize_t read(char* ptr, size_t size) override {
    if (hit_ != BoundHit::kNone) return -1;
    if (size == 0) return 0;
    if (!Buffered()) {
      // A request's bytes must all arrive by its deadline: a client that drips its body holds
      // a worker that long at most, whatever read timeout each byte meets.
      if (!Poll(sock_, POLLIN, ReadWaitMs())) return -1;
      buffer_.resize(kReadBufferBytes);
      ssize_t n = 0;
      do {
        n = ::recv(sock_, buffer_.data(), buffer_.size(), MSG_DONTWAIT);
      } while (n < 0 && errno == EINTR);
      buffer_.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
      off_ = 0;
      if (n <= 0) return n;
    }
    std::size_t n = std::min(size, buffer_.size() - off_);
    if (in_head_) {
      n = HeadBytes(n);
      if (n == 0) return -1;
    } else {
      if (body_read_ + n > bounds_.body_bytes) n = bounds_.body_bytes - body_read_;
      if (n == 0) {
        hit_ = BoundHit::kBody;
        return -1;
      }
      body_read_ += n;
    }
    std::memcpy(ptr, buffer_.data() + off_, n);
    off_ += n;
    return static_cast<ssize_t>(n);
  }

  // Never blocks longer than the write timeout in all: a client that stops reading (an event
  // stream to a page that hangs) fails the write and frees its worker once its buffers are full.
  ssize_t write(const char* ptr, size_t size) override {
    const auto end = Clock::now() + std::chrono::milliseconds(write_timeout_ms_);
    for (;;) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(end - Clock::now()).count();
      if (left <= 0 || !Poll(sock_, POLLOUT, static_cast<int>(left))) return -1;
      ssize_t n = 0;
      do {
        n = ::send(sock_, ptr, size, MSG_NOSIGNAL | MSG_DONTWAIT);
      } while (n < 0 && errno == EINTR);
      if (n >= 0 || (errno != EAGAIN && errno != EWOULDBLOCK)) return n;
    }
  }

  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    sockaddr_storage addr{};
    socklen_t len = sizeof(addr);
    if (::getpeername(sock_, reinterpret_cast<sockaddr*>(&addr), &len) == 0)
      AddressOf(addr, len, ip, port);
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    sockaddr_storage addr{};
    socklen_t len = sizeof(addr);
    if (::getsockname(sock_, reinterpret_cast<sockaddr*>(&addr), &len) == 0)
      AddressOf(addr, len, ip, port);
  }
  socket_t socket() const override { return sock_; }

 private:
  int ReadWaitMs() const {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(read_deadline_ - Clock::now());
    return static_cast<int>(std::clamp<long long>(left.count(), 0, read_timeout_ms_));
  }

  // How many of the next `n` buffered bytes belong to the head (up to and including the blank
  // line that ends it, as cpp-httplib reads it: "\r\n" alone); 0 when the head bound is passed.
  std::size_t HeadBytes(std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
      if (head_read_ == bounds_.head_bytes) {
        hit_ = BoundHit::kHead;
        return 0;
      }
      ++head_read_;
      const char c = buffer_[off_ + i];
      if (c == '\n') {
        const bool blank = line_bytes_ == 1 && line_cr_;
        line_bytes_ = 0;
        line_cr_ = false;
        if (blank && lines_ > 0) {
          in_head_ = false;
          return i + 1;
        }
        ++lines_;
      } else {
        ++line_bytes_;
        line_cr_ = c == '\r';
      }
    }
    return n;
  }

  // A peer that closed its end shows as readable with nothing to read (cpp-httplib's check too:
  // an event stream to a closed page stops at its next write).
  bool PeerStillThere() const {
    if (Buffered() || !Poll(sock_, POLLIN, 0)) return true;
    char byte = 0;
    return ::recv(sock_, &byte, 1, MSG_PEEK | MSG_DONTWAIT) != 0;
  }

  int sock_;
  RequestBounds bounds_;
  std::string buffer_;
  std::size_t off_ = 0;
  Clock::time_point read_deadline_;
  int read_timeout_ms_;
  int write_timeout_ms_;
  bool in_head_ = true;
  std::size_t head_read_ = 0;
  std::size_t body_read_ = 0;
  std::size_t line_bytes_ = 0;
  bool line_cr_ = false;
  std::size_t lines_ = 0;
  BoundHit hit_ = BoundHit::kNone;
  bool close_ = false;
};

thread_local BoundedStream* current_stream = nullptr;

// A head too large to be parsed at all (its request line alone passed the bound): cpp-httplib
// then gives up without an answer, so the answer is written here.
void WriteHeadRefusal(BoundedStream& stream, std::size_t head_bytes) {
  const std::string body = "{\"error\":\"the request's line and headers are too large (at most " +
                           std::to_string(head_bytes / 1024) + " kB)\"}";
  const std::string text =
      "HTTP/1.1 431 Request Header Fields Too Large\r\nContent-Type: application/json\r\n"
      "Connection: close\r\nContent-Length: " +
      std::to_string(body.size()) + "\r\n\r\n" + body;
  (void)stream.write(text.data(), text.size());
}

}  // namespace

BoundedServer::BoundedServer(RequestBounds bounds) : bounds_(bounds) {}

BoundHit BoundedServer::CurrentRequestHit() {
  return current_stream != nullptr ? current_stream->Hit() : BoundHit::kNone;
}

void BoundedServer::CloseConnectionAfterResponse() {
  if (current_stream != nullptr) current_stream->CloseAfterResponse();
}

bool BoundedServer::Bind(const std::string& host, int port, int backlog) {
  if (!bind_to_port(host, port)) return false;
  // cpp-httplib listens with a backlog of 5 (compiled into Debian's library); listen() again on
  // a listening socket changes only its backlog (Linux), so a burst of browsers and scripts is
  // queued by the kernel rather than refused.
  const int sock = svr_sock_;
  ::listen(sock, backlog);
  ::fcntl(sock, F_SETFL, ::fcntl(sock, F_GETFL) | O_NONBLOCK);  // the gate accepts in a loop
  return true;
}

int BoundedServer::ListenSocket() const { return svr_sock_; }

void BoundedServer::CloseListenSocket() {
  const int sock = svr_sock_.exchange(INVALID_SOCKET);
  if (sock != INVALID_SOCKET) ::close(sock);
}

Served BoundedServer::ServeOne(int sock, std::string buffered,
                               std::chrono::steady_clock::time_point read_deadline) {
  BoundedStream stream(sock, bounds_, std::move(buffered), read_deadline,
                       ToMs(read_timeout_sec_, read_timeout_usec_),
                       ToMs(write_timeout_sec_, write_timeout_usec_));
  bool closed = false;
  current_stream = &stream;
  const bool ok = process_request(stream, svr_sock_ == INVALID_SOCKET, closed, nullptr);
  current_stream = nullptr;
  if (!ok && stream.Hit() == BoundHit::kHead) WriteHeadRefusal(stream, bounds_.head_bytes);
  Served served;
  if (stream.Closing())
    served.next = Served::Next::kDrain;
  else if (!ok || closed)
    served.next = Served::Next::kClose;
  else
    served.unread = stream.Unread();
  return served;
}

void ExclusiveListenSocket(socket_t sock) {
  int yes = 1;
  ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
}

}  // namespace hrgbench::app
