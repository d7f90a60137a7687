#pragma once
// The event stream's transport: one JSON object per line, written to a file descriptor by a writer
// thread of its own, fed through a bounded queue (issue 11 §1).
//
// Why a queue and a thread: the producer is the sequencer's thread, which drains the capture ring;
// if it waited for a slow reader (a full pipe, a stopped browser) the ring would overflow and
// samples would be lost. So Publish never waits for the reader: it takes a mutex held only for a
// push or a swap (never across a write), and when the queue is full the event is dropped and
// counted. A slow or gone reader loses events, never samples.
//
// Every event gets, in this order: "v" (kEventFormatVersion), "seq" (0, 1, 2, ... in Publish order,
// dropped events included, so a reader sees a gap where it lost one), "time_unix_s" (wall clock at
// Publish, s since 1970, ms resolution), "type", then the event's own fields (sorted by name).
//
// The writer writes at most PIPE_BUF bytes per write() after poll() says the descriptor is
// writable, so it never blocks on a pipe either and notices Close() within kPollPeriodMs. A write
// error (EPIPE: the reader went away) ends writing: every later event is counted lost. SIGPIPE must
// be ignored by the process (hrg-bench does); otherwise a gone reader kills it.
//
// Close() ends the stream with a last event, type "end", carrying "events_published" and
// "events_lost" (every event before it that did not reach the descriptor), after waiting up to
// `drain_timeout_ms` for the queue to drain; the end event gets kEndGraceNs more at most. No line
// is begun after the deadline; a line begun before it gets kEndGraceNs to be finished. A line cut
// short even so is the last thing written (write_error says so): the descriptor never holds a
// broken line followed by more. Threads: Publish from any thread;
// Open/Close from one owner thread.

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <expected>
#include <filesystem>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

namespace hrgbench::bench {

inline constexpr int kEventFormatVersion = 1;

struct EventStreamStats {
  std::uint64_t published = 0;  // events given to Publish (the "end" event not counted)
  std::uint64_t written = 0;    // reached the descriptor in full
  std::uint64_t lost = 0;       // dropped: queue full, write error, or not drained by Close
  bool end_written = false;     // the "end" event reached the descriptor
  std::string write_error;      // the first write error (empty: none)
};

class EventStream {
 public:
  static constexpr std::size_t kDefaultCapacity = 4096;  // events: minutes of progress at 5 Hz
  static constexpr int kPollPeriodMs = 50;

  // "-" is standard output (a dup of it, so closing never closes fd 1); anything else a new file,
  // an earlier event stream (replaced: its first line begins {"v":) or an empty file, a FIFO that
  // has a reader (refused at once when it has none: never blocks), or a device. Any other existing
  // file (a session.json) is refused, not truncated. Fails with the path and the reason.
  static std::expected<std::unique_ptr<EventStream>, std::string> Open(const std::string& target,
                                                                       std::size_t capacity);
  // Takes ownership of `fd` (closed by Close or the destructor). For tests and the panel's pipe.
  static std::unique_ptr<EventStream> FromFd(int fd, std::size_t capacity);

  ~EventStream();
  EventStream(const EventStream&) = delete;
  EventStream& operator=(const EventStream&) = delete;

  // Stamps and queues `event` (an object with at least "type"); never waits for the reader.
  // After Close: counted lost.
  void Publish(nlohmann::json event);

  // Waits up to drain_timeout_ms for the queue to reach the descriptor, writes the "end" event
  // (given the same time to go), stops the writer and closes the descriptor. Idempotent.
  EventStreamStats Close(int drain_timeout_ms = 2000);

  EventStreamStats Stats() const;

 private:
  struct Queued {
    std::uint64_t seq;
    nlohmann::json event;
  };
  EventStream(int fd, std::size_t capacity);
  void WriterLoop();
  // Writes all of `line` before drain_deadline_ns_ (0: none; a line begun, kEndGraceNs after it).
  // False when it did not.
  bool WriteLine(const std::string& line);
  static constexpr std::int64_t kEndGraceNs = 500'000'000;

  int fd_;
  std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Queued> queue_;
  std::uint64_t next_seq_ = 0;
  bool closing_ = false;
  bool stop_ = false;
  std::int64_t drain_deadline_ns_ = 0;  // steady clock; set by Close
  EventStreamStats stats_;
  std::thread writer_;
};

}  // namespace hrgbench::bench
