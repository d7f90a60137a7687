#include "app/panel/panel_http.hpp"

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
// After a refusal: what is drained at most, so the client reads the answer instead of a reset
// (closing a socket with unread input makes the kernel reset the connection).
constexpr std::size_t kDrainBytes = 1 << 20;
constexpr auto kDrainTime = std::chrono::milliseconds(1000);
// ... and the drain stops when the client pauses this long: a browser closes as soon as it sees
// the end of the answer, and a client that neither sends nor closes must not hold a worker.
constexpr auto kDrainGap = std::chrono::milliseconds(200);
constexpr auto kStopPoll = std::chrono::milliseconds(100);  // how soon a stop ends an idle wait

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
class BoundedStream final : public httplib::Stream {
 public:
  BoundedStream(int sock, const RequestBounds& bounds, int read_timeout_ms, int write_timeout_ms)
      : sock_(sock),
        bounds_(bounds),
        read_timeout_ms_(read_timeout_ms),
        write_timeout_ms_(write_timeout_ms) {}

  void NextRequest() {
    in_head_ = true;
    head_read_ = 0;
    body_read_ = 0;
    line_bytes_ = 0;
    line_cr_ = false;
    lines_ = 0;
  }
  bool Buffered() const { return off_ < len_; }
  BoundHit Hit() const { return hit_; }
  void CloseAfterResponse() { close_ = true; }
  bool Closing() const { return close_ || hit_ != BoundHit::kNone; }

  bool is_readable() const override { return Buffered() || Poll(sock_, POLLIN, read_timeout_ms_); }
  bool is_writable() const override {
    return Poll(sock_, POLLOUT, write_timeout_ms_) && PeerStillThere();
  }

  ssize_t read(char* ptr, size_t size) override {
    if (hit_ != BoundHit::kNone) return -1;
    if (size == 0) return 0;
    if (!Buffered()) {
      if (!Poll(sock_, POLLIN, read_timeout_ms_)) return -1;
      ssize_t n = 0;
      do {
        n = ::recv(sock_, buffer_.data(), buffer_.size(), 0);
      } while (n < 0 && errno == EINTR);
      if (n <= 0) return n;
      off_ = 0;
      len_ = static_cast<std::size_t>(n);
    }
    std::size_t n = std::min(size, len_ - off_);
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

  ssize_t write(const char* ptr, size_t size) override {
    if (!Poll(sock_, POLLOUT, write_timeout_ms_)) return -1;
    ssize_t n = 0;
    do {
      n = ::send(sock_, ptr, size, MSG_NOSIGNAL);
    } while (n < 0 && errno == EINTR);
    return n;
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
  int read_timeout_ms_;
  int write_timeout_ms_;
  std::array<char, kReadBufferBytes> buffer_{};
  std::size_t off_ = 0;
  std::size_t len_ = 0;
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

// Lets the client read the refusal: no more writes, then what it still sends is read and thrown
// away, within a bound of bytes and time.
void DrainBeforeClose(int sock) {
  ::shutdown(sock, SHUT_WR);
  std::array<char, kReadBufferBytes> sink{};
  std::size_t drained = 0;
  const auto end = Clock::now() + kDrainTime;
  while (drained < kDrainBytes && Clock::now() < end) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - Clock::now());
    if (!Poll(sock, POLLIN, static_cast<int>(std::min(left, kDrainGap).count()) + 1)) break;
    const ssize_t n = ::recv(sock, sink.data(), sink.size(), 0);
    if (n <= 0) break;
    drained += static_cast<std::size_t>(n);
  }
}

}  // namespace

BoundedServer::BoundedServer(RequestBounds bounds) : bounds_(bounds) {}

BoundHit BoundedServer::CurrentRequestHit() {
  return current_stream != nullptr ? current_stream->Hit() : BoundHit::kNone;
}

void BoundedServer::CloseConnectionAfterResponse() {
  if (current_stream != nullptr) current_stream->CloseAfterResponse();
}

bool BoundedServer::process_and_close_socket(socket_t sock) {
  BoundedStream stream(sock, bounds_, ToMs(read_timeout_sec_, read_timeout_usec_),
                       ToMs(write_timeout_sec_, write_timeout_usec_));
  bool ok = false;
  for (std::size_t left = keep_alive_max_count_; left > 0 && svr_sock_ != INVALID_SOCKET; --left) {
    // The next request: cpp-httplib's keep-alive wait, in slices so that a stop ends it.
    const auto idle_end = Clock::now() + std::chrono::seconds(keep_alive_timeout_sec_);
    bool arrived = stream.Buffered();
    while (!arrived && svr_sock_ != INVALID_SOCKET && Clock::now() < idle_end)
      arrived = Poll(sock, POLLIN, static_cast<int>(kStopPoll.count()));
    if (!arrived) break;
    stream.NextRequest();
    bool closed = false;
    current_stream = &stream;
    ok = process_request(stream, left == 1, closed, nullptr);
    current_stream = nullptr;
    if (!ok && stream.Hit() == BoundHit::kHead) WriteHeadRefusal(stream, bounds_.head_bytes);
    if (!ok || closed || stream.Closing()) break;
  }
  if (stream.Closing()) DrainBeforeClose(sock);
  ::shutdown(sock, SHUT_RDWR);
  ::close(sock);
  return ok;
}

void ExclusiveListenSocket(socket_t sock) {
  int yes = 1;
  ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
}

}  // namespace hrgbench::app
