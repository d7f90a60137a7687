#include "app/panel/panel_gate.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <thread>

// Last: it brings <httplib.h>.
#include "app/panel/panel_http.hpp"  // NOLINT(llvm-include-order)

namespace hrgbench::app {
namespace {

using Clock = std::chrono::steady_clock;

// A refused request's connection: what is read and dropped at most before it is closed.
constexpr std::size_t kDrainBytes = 1 << 20;
constexpr auto kDrainTime = std::chrono::milliseconds(1000);
constexpr std::size_t kRecvBytes = 16 * 1024;
// An event stream's send buffer: small, so that a page that stops reading fills it (and the
// stream's write times out) after a few events instead of megabytes of them.
constexpr int kStreamSendBufferBytes = 64 * 1024;

enum class Held {
  kNew,       // accepted, nothing read yet
  kIdle,      // keep-alive, between requests
  kReading,   // part of a request
  kDraining,  // refused: reading and dropping until the client closes or the drain ends
};

struct Conn {
  std::string address;
  std::string buffer;
  Held state = Held::kNew;
  Clock::time_point deadline;
  std::uint64_t since = 0;  // order of entering the gate's hold: the smallest is evicted first
  std::size_t drained = 0;
};

std::string PeerAddress(const sockaddr_storage& addr) {
  char text[INET6_ADDRSTRLEN] = {};
  if (addr.ss_family == AF_INET)
    ::inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in&>(addr).sin_addr, text, sizeof text);
  else if (addr.ss_family == AF_INET6)
    ::inet_ntop(AF_INET6, &reinterpret_cast<const sockaddr_in6&>(addr).sin6_addr, text,
                sizeof text);
  return text;
}

// A short refusal, written without waiting: it fits in the socket's empty send buffer, and a
// client that does not read it loses nothing the gate would wait for.
void Answer(int fd, int status, std::string_view reason, const std::string& message,
            std::string_view extra_headers = {}) {
  const std::string body = "{\"error\":\"" + message + "\"}";
  const std::string text = "HTTP/1.1 " + std::to_string(status) + " " + std::string(reason) +
                           "\r\nContent-Type: application/json\r\nConnection: close\r\n" +
                           std::string(extra_headers) +
                           "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
  (void)::send(fd, text.data(), text.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
}

char Lower(char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); }

// Where the value of header `name` ("\r\nname:", lower case) starts in a head, or npos.
std::size_t HeaderValue(std::string_view head, std::string_view name) {
  const auto at = std::search(head.begin(), head.end(), name.begin(), name.end(),
                              [](char a, char b) { return Lower(a) == b; });
  return at == head.end() ? std::string_view::npos
                          : static_cast<std::size_t>(at - head.begin()) + name.size();
}

// The Content-Length of a head (its lines after the request line), if it has one that parses.
std::optional<std::size_t> ContentLength(std::string_view head) {
  std::size_t i = HeaderValue(head, "\r\ncontent-length:");
  if (i == std::string_view::npos) return std::nullopt;
  while (i < head.size() && (head[i] == ' ' || head[i] == '\t')) ++i;
  std::size_t value = 0;
  const auto [end, ec] = std::from_chars(head.data() + i, head.data() + head.size(), value);
  if (ec != std::errc() || end == head.data() + i) return std::nullopt;
  return value;
}

}  // namespace

PanelGate::PanelGate(BoundedServer& server, GateLimits limits, Classify classify)
    : server_(server),
      limits_(limits),
      classify_(std::move(classify)),
      wake_(::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK)) {}

PanelGate::~PanelGate() { ::close(wake_); }

void PanelGate::Stop() {
  stop_ = true;
  const std::uint64_t one = 1;
  (void)!::write(wake_, &one, sizeof one);
}

void PanelGate::GiveBack(Handback handback) {
  const std::lock_guard lock(handback_mutex_);
  if (stop_) {
    ::close(handback.fd);
    return;
  }
  handbacks_.push_back(std::move(handback));
  const std::uint64_t one = 1;
  (void)!::write(wake_, &one, sizeof one);
}

void PanelGate::Serve() {
  const std::size_t head_bytes = server_.bounds().head_bytes;
  httplib::ThreadPool general(limits_.general_threads);
  httplib::ThreadPool streams(limits_.max_streams);
  httplib::ThreadPool control(limits_.control_threads);
  httplib::ThreadPool abort(limits_.abort_threads);
  const auto pool_of = [&](Lane lane) -> httplib::ThreadPool& {
    switch (lane) {
      case Lane::kStream:
        return streams;
      case Lane::kControl:
        return control;
      case Lane::kAbort:
        return abort;
      case Lane::kGeneral:
        break;
    }
    return general;
  };

  std::map<int, Conn> held;            // no complete request yet: polled here
  std::map<int, std::string> serving;  // on a worker: fd -> client address
  std::map<std::string, std::size_t> per_address;
  std::size_t open_streams = 0;
  std::uint64_t order = 0;

  const auto forget = [&](const std::string& address) {
    if (--per_address[address] == 0) per_address.erase(address);
  };
  const auto close_held = [&](std::map<int, Conn>::iterator it) {
    ::close(it->first);
    forget(it->second.address);
    held.erase(it);
  };
  const auto drain = [&](int fd, Conn& conn) {
    ::shutdown(fd, SHUT_WR);
    conn.state = Held::kDraining;
    conn.buffer.clear();
    conn.drained = 0;
    conn.deadline = Clock::now() + kDrainTime;
  };
  // The connection held longest (of `address`, or of anyone when empty).
  const auto oldest = [&](const std::string& address) {
    auto best = held.end();
    for (auto it = held.begin(); it != held.end(); ++it)
      if ((address.empty() || it->second.address == address) &&
          (best == held.end() || it->second.since < best->second.since))
        best = it;
    return best;
  };

  // Decides on a held connection's buffer: wait for more, refuse, or hand it to its lane.
  const auto examine = [&](std::map<int, Conn>::iterator it) {
    const int fd = it->first;
    Conn& conn = it->second;
    const std::size_t end = conn.buffer.find("\r\n\r\n");
    if (end == std::string::npos || end + 4 > head_bytes) {
      if (conn.buffer.size() > head_bytes || end != std::string::npos) {
        Answer(fd, 431, "Request Header Fields Too Large",
               "the request's line and headers are too large (at most " +
                   std::to_string(head_bytes / 1024) + " kB)");
        drain(fd, conn);
      }
      return;
    }
    const std::string_view text(conn.buffer);
    const std::string_view line = text.substr(0, text.find("\r\n"));
    const std::size_t space = line.find(' ');
    const std::string_view method = line.substr(0, space);
    std::string_view target =
        space == std::string_view::npos ? std::string_view() : line.substr(space + 1);
    target = target.substr(0, target.find(' '));
    const std::string_view path = target.substr(0, target.find('?'));
    if (method != "GET" && method != "POST" && method != "HEAD") {
      Answer(fd, 405, "Method Not Allowed",
             "the panel answers GET, POST and HEAD only (not " + std::string(method.substr(0, 16)) +
                 ")",
             "Allow: GET, POST, HEAD\r\n");
      drain(fd, conn);
      return;
    }
    // A small body is read here, so that no lane's thread waits for a client's bytes.
    // (Not when the client waits for "100 Continue" before it sends the body.)
    const std::string_view head = text.substr(0, end + 2);
    const auto length = ContentLength(head);
    if (length && *length <= limits_.body_wait_bytes && conn.buffer.size() < end + 4 + *length &&
        HeaderValue(head, "\r\nexpect:") == std::string_view::npos)
      return;
    const Lane lane = classify_(method, path);
    if (lane == Lane::kStream && open_streams >= limits_.max_streams) {
      Answer(fd, 503, "Service Unavailable",
             "too many event streams are open (" + std::to_string(limits_.max_streams) +
                 "): close a panel page and reload",
             "Retry-After: 5\r\n");
      drain(fd, conn);
      return;
    }
    if (lane == Lane::kStream) {
      ++open_streams;
      ::setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &kStreamSendBufferBytes,
                   sizeof kStreamSendBufferBytes);
    }
    serving.emplace(fd, conn.address);
    const auto deadline = Clock::now() + limits_.head_timeout;
    pool_of(lane).enqueue([this, fd, lane, deadline, buffered = std::move(conn.buffer)]() mutable {
      Served served = server_.ServeOne(fd, std::move(buffered), deadline);
      GiveBack({fd, served.next == Served::Next::kKeep, served.next == Served::Next::kDrain,
                std::move(served.unread), lane});
    });
    held.erase(it);
  };

  const auto hold = [&](int fd, const std::string& address, Held state, std::string buffer) {
    Conn conn;
    conn.address = address;
    conn.buffer = std::move(buffer);
    conn.state = state;
    conn.since = ++order;
    conn.deadline =
        Clock::now() + (state == Held::kIdle ? limits_.idle_timeout : limits_.head_timeout);
    return held.insert_or_assign(fd, std::move(conn)).first;
  };

  const auto accept_all = [&](int listen_fd) {
    for (;;) {
      sockaddr_storage addr{};
      socklen_t len = sizeof addr;
      const int fd = ::accept4(listen_fd, reinterpret_cast<sockaddr*>(&addr), &len, SOCK_CLOEXEC);
      if (fd < 0) {
        if (errno == EINTR || errno == ECONNABORTED) continue;
        if (errno == EMFILE || errno == ENFILE)  // out of descriptors: the next round retries
          std::this_thread::sleep_for(std::chrono::milliseconds(1));
        return;
      }
      const std::string address = PeerAddress(addr);
      std::string over;
      auto victim = held.end();
      const auto from = per_address.find(address);
      if (from != per_address.end() && from->second >= limits_.max_per_address) {
        victim = oldest(address);
        over = "too many connections from " + address;
      } else if (held.size() + serving.size() >= limits_.max_connections) {
        victim = oldest("");
        over = "too many connections";
      }
      if (!over.empty()) {
        if (victim == held.end()) {
          Answer(fd, 503, "Service Unavailable", over + ": try again", "Retry-After: 1\r\n");
          ::close(fd);
          continue;
        }
        close_held(victim);
      }
      ++per_address[address];
      hold(fd, address, Held::kNew, {});
    }
  };

  const auto take_handbacks = [&] {
    std::vector<Handback> back;
    {
      const std::lock_guard lock(handback_mutex_);
      back.swap(handbacks_);
    }
    for (Handback& h : back) {
      const auto at = serving.find(h.fd);
      const std::string address = at->second;
      serving.erase(at);
      if (h.lane == Lane::kStream) --open_streams;
      if (!h.keep && !h.drain) {
        ::close(h.fd);
        forget(address);
        continue;
      }
      auto it = hold(h.fd, address, h.drain ? Held::kDraining : Held::kIdle, std::move(h.unread));
      if (h.drain) {
        drain(h.fd, it->second);
      } else if (!it->second.buffer.empty()) {
        it->second.state = Held::kReading;
        it->second.deadline = Clock::now() + limits_.head_timeout;
        examine(it);
      }
    }
  };

  const auto read_from = [&](std::map<int, Conn>::iterator it) {
    Conn& conn = it->second;
    char chunk[kRecvBytes];
    ssize_t n = 0;
    do {
      n = ::recv(it->first, chunk, sizeof chunk, MSG_DONTWAIT);
    } while (n < 0 && errno == EINTR);
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return;
    if (n <= 0) return close_held(it);
    if (conn.state == Held::kDraining) {
      conn.drained += static_cast<std::size_t>(n);
      if (conn.drained > kDrainBytes) close_held(it);
      return;
    }
    if (conn.state != Held::kReading) {
      conn.state = Held::kReading;
      conn.deadline = Clock::now() + limits_.head_timeout;
    }
    conn.buffer.append(chunk, static_cast<std::size_t>(n));
    examine(it);
  };

  const auto expire = [&] {
    const auto now = Clock::now();
    for (auto it = held.begin(); it != held.end();) {
      auto next = std::next(it);
      if (it->second.deadline <= now) {
        if (it->second.state == Held::kReading)
          Answer(it->first, 408, "Request Timeout",
                 "the request did not arrive in time: the panel waits " +
                     std::to_string(limits_.head_timeout.count()) + " ms for a request's head");
        close_held(it);
      }
      it = next;
    }
  };

  std::vector<pollfd> fds;
  while (!stop_) {
    const int listen_fd = server_.ListenSocket();
    fds.clear();
    fds.push_back({wake_, POLLIN, 0});
    fds.push_back({listen_fd, POLLIN, 0});
    auto next_deadline = Clock::now() + std::chrono::seconds(1);
    for (const auto& [fd, conn] : held) {
      fds.push_back({fd, POLLIN, 0});
      next_deadline = std::min(next_deadline, conn.deadline);
    }
    const auto wait =
        std::chrono::duration_cast<std::chrono::milliseconds>(next_deadline - Clock::now()) +
        std::chrono::milliseconds(1);
    const int ready =
        ::poll(fds.data(), fds.size(), static_cast<int>(std::max<long long>(0, wait.count())));
    if (ready < 0 && errno != EINTR) break;
    if (stop_) break;
    if (fds[0].revents != 0) {
      std::uint64_t count = 0;
      (void)!::read(wake_, &count, sizeof count);
      take_handbacks();
    }
    for (std::size_t i = 2; i < fds.size(); ++i) {
      if (fds[i].revents == 0) continue;
      const auto it = held.find(fds[i].fd);
      if (it != held.end()) read_from(it);
    }
    if (fds[1].revents != 0) accept_all(listen_fd);
    expire();
  }

  // Stopping: no new connection; the workers' connections close as their responses end.
  {
    const std::lock_guard lock(handback_mutex_);
    stop_ = true;
    for (const Handback& h : handbacks_) ::close(h.fd);
    handbacks_.clear();
  }
  for (const auto& [fd, conn] : held) ::close(fd);
  server_.CloseListenSocket();
  general.shutdown();
  streams.shutdown();
  control.shutdown();
  abort.shutdown();
}

}  // namespace hrgbench::app
