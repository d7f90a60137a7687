#include "hrgbench/bench/events/event_stream.hpp"

#include <fcntl.h>
#include <limits.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace hrgbench::bench {
namespace {

std::int64_t SteadyNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

double UnixSeconds() {
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                      std::chrono::system_clock::now().time_since_epoch())
                      .count();
  return static_cast<double>(ms) * 1e-3;
}

// The line for one event: the stream's fields first (a reader can check version and order before
// it parses the rest), then "type", then the event's own fields.
std::string Line(std::uint64_t seq, nlohmann::json event) {
  std::string type = "unknown";
  double time_unix_s = UnixSeconds();
  if (event.is_object()) {
    if (auto it = event.find("type"); it != event.end() && it->is_string()) type = *it;
    event.erase("type");
    if (auto it = event.find("time_unix_s"); it != event.end() && it->is_number()) {
      time_unix_s = *it;
      event.erase("time_unix_s");
    }
  } else {
    event = nlohmann::json::object();
  }
  char stamp[32];  // ms resolution, as measured: no binary-fraction digits after it
  std::snprintf(stamp, sizeof stamp, "%.3f", time_unix_s);
  std::string line = "{\"v\":" + std::to_string(kEventFormatVersion) +
                     ",\"seq\":" + std::to_string(seq) + ",\"time_unix_s\":" + stamp +
                     ",\"type\":" + nlohmann::json(type).dump();
  const std::string rest = event.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  if (rest.size() > 2)
    line += "," + rest.substr(1);
  else
    line += "}";
  line += '\n';
  return line;
}

// Whether an existing regular file is an earlier event stream (or empty), which may be replaced:
// every line this stream writes begins with {"v":. Anything else (another session's session.json,
// a report) is not ours to truncate.
bool IsEventStreamOrEmpty(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return false;
  char head[5] = {};
  const ssize_t n = ::read(fd, head, sizeof head);
  ::close(fd);
  return n == 0 || (n == static_cast<ssize_t>(sizeof head) && std::memcmp(head, "{\"v\":", 5) == 0);
}

// --events FILE: a new file, an earlier event stream (replaced), a FIFO with a reader, or a device
// (/dev/null). A FIFO is opened without blocking: with no reader yet the open fails at once
// (ENXIO) and the session does not start, where a blocking open would wait forever before it.
std::expected<int, std::string> OpenTarget(const std::string& target) {
  const std::string where = "--events " + target + ": ";
  struct stat st {};
  if (::stat(target.c_str(), &st) == 0) {
    if (S_ISFIFO(st.st_mode)) {
      const int fd = ::open(target.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
      if (fd < 0 && errno == ENXIO)
        return std::unexpected(where + "a FIFO with no reader: start the reader first (e.g. `cat " +
                               target + "`), then the session");
      if (fd < 0) return std::unexpected(where + "cannot open: " + std::strerror(errno));
      // The writer thread waits for a slow reader (the queue counts what it cannot hold).
      const int flags = ::fcntl(fd, F_GETFL);
      if (flags >= 0) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
      return fd;
    }
    if (S_ISDIR(st.st_mode)) return std::unexpected(where + "is a directory");
    if (S_ISREG(st.st_mode) && !IsEventStreamOrEmpty(target))
      return std::unexpected(where +
                             "exists and is not an event stream: not overwritten; give a new "
                             "file, - (stdout) or a FIFO");
  }
  const int fd = ::open(target.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return std::unexpected(where + "cannot open: " + std::strerror(errno));
  return fd;
}

}  // namespace

std::expected<std::unique_ptr<EventStream>, std::string> EventStream::Open(
    const std::string& target, std::size_t capacity) {
  int fd = -1;
  if (target == "-") {
    fd = ::fcntl(STDOUT_FILENO, F_DUPFD_CLOEXEC, 3);
    if (fd < 0)
      return std::unexpected("--events -: cannot use standard output: " +
                             std::string(std::strerror(errno)));
  } else {
    auto opened = OpenTarget(target);
    if (!opened) return std::unexpected(opened.error());
    fd = *opened;
  }
  return FromFd(fd, capacity);
}

std::unique_ptr<EventStream> EventStream::FromFd(int fd, std::size_t capacity) {
  return std::unique_ptr<EventStream>(new EventStream(fd, capacity == 0 ? 1 : capacity));
}

EventStream::EventStream(int fd, std::size_t capacity) : fd_(fd), capacity_(capacity) {
  writer_ = std::thread([this] { WriterLoop(); });
}

EventStream::~EventStream() { Close(0); }

void EventStream::Publish(nlohmann::json event) {
  if (event.is_object() && !event.contains("time_unix_s")) event["time_unix_s"] = UnixSeconds();
  {
    const std::lock_guard lock(mutex_);
    const std::uint64_t seq = next_seq_++;
    ++stats_.published;
    if (closing_ || queue_.size() >= capacity_) {
      ++stats_.lost;
      return;
    }
    queue_.push_back({seq, std::move(event)});
  }
  wake_.notify_one();
}

bool EventStream::WriteLine(const std::string& line) {
  std::size_t done = 0;
  while (done < line.size()) {
    {
      // The deadline is read afresh: Close may set it while a line waits for a stopped reader.
      const std::lock_guard lock(mutex_);
      if (stop_) return false;
      // After the drain deadline no line is begun; one already begun gets the end's grace to be
      // finished, because half a line on the descriptor would leave nothing after it parseable
      // (a reader slower than the session's end got a torn last line and no "end").
      const std::int64_t limit = done == 0 ? drain_deadline_ns_ : drain_deadline_ns_ + kEndGraceNs;
      if (drain_deadline_ns_ != 0 && SteadyNs() >= limit) {
        if (done > 0 && stats_.write_error.empty()) stats_.write_error = "a line was cut short";
        return false;
      }
    }
    pollfd p{fd_, POLLOUT, 0};
    const int ready = ::poll(&p, 1, kPollPeriodMs);
    if (ready < 0 && errno == EINTR) continue;
    if (ready < 0 || (p.revents & (POLLERR | POLLNVAL)) != 0) {
      const std::lock_guard lock(mutex_);
      if (stats_.write_error.empty()) stats_.write_error = "the reader went away";
      return false;
    }
    if (ready == 0) continue;  // full: the reader is slow; look at stop_ and the deadline again
    // At most PIPE_BUF: a pipe that poll() calls writable takes that much without blocking.
    const std::size_t chunk = std::min<std::size_t>(line.size() - done, PIPE_BUF);
    const ssize_t n = ::write(fd_, line.data() + done, chunk);
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN) continue;
      const std::lock_guard lock(mutex_);
      if (stats_.write_error.empty()) stats_.write_error = std::strerror(errno);
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  return true;
}

void EventStream::WriterLoop() {
  std::deque<Queued> batch;
  bool broken = false;
  for (;;) {
    bool closing = false;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || closing_ || !queue_.empty(); });
      if (stop_) break;
      batch.swap(queue_);
      closing = closing_;
    }
    while (!batch.empty()) {
      const bool ok = !broken && WriteLine(Line(batch.front().seq, std::move(batch.front().event)));
      batch.pop_front();
      const std::lock_guard lock(mutex_);
      if (ok) {
        ++stats_.written;
      } else {
        ++stats_.lost;
        broken = broken || !stats_.write_error.empty();
      }
    }
    if (closing) {
      std::unique_lock lock(mutex_);
      if (!queue_.empty()) continue;  // published before closing_ was seen
      nlohmann::json end;
      end["type"] = "end";
      end["events_published"] = stats_.published;
      end["events_lost"] = stats_.lost;
      const std::uint64_t seq = next_seq_++;
      // The end gets a moment of its own even when the drain used all of its time.
      drain_deadline_ns_ = std::max(drain_deadline_ns_, SteadyNs() + kEndGraceNs);
      lock.unlock();
      const bool ok = !broken && WriteLine(Line(seq, std::move(end)));
      lock.lock();
      stats_.end_written = ok;
      break;
    }
  }
}

EventStreamStats EventStream::Close(int drain_timeout_ms) {
  {
    const std::lock_guard lock(mutex_);
    if (!writer_.joinable()) return stats_;
    closing_ = true;
    // Never 0 (0 means no deadline).
    drain_deadline_ns_ =
        std::max<std::int64_t>(1, SteadyNs() + std::int64_t{drain_timeout_ms} * 1'000'000);
  }
  wake_.notify_one();
  writer_.join();
  ::close(fd_);
  const std::lock_guard lock(mutex_);
  stop_ = true;
  return stats_;
}

EventStreamStats EventStream::Stats() const {
  const std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace hrgbench::bench
