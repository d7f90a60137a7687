#pragma once
// hrg-bench's --events: the event stream of one run or resume (bench/event_stream.hpp,
// bench/session_events.hpp) and its account in the session folder.
//
// <session>/events.json, written when the stream closes: {"format_version", "target",
// "events_published", "events_written", "events_lost", "end_written", "write_error"}: the record of
// what a reader may have missed (a slow or gone reader loses events, never samples).

#include <expected>
#include <filesystem>
#include <memory>
#include <string>

#include "hrgbench/bench/events/event_stream.hpp"
#include "hrgbench/bench/events/session_events.hpp"

namespace hrgbench::app {

class EventOutput {
 public:
  // target: "-" (stdout) or a file path; capacity: the queue's, in events (> 0).
  static std::expected<std::unique_ptr<EventOutput>, std::string> Open(const std::string& target,
                                                                       std::size_t capacity);
  bench::SessionEventPublisher& publisher() { return publisher_; }
  // Ends the stream (its "end" event) and writes <session_dir>/events.json when the folder exists.
  void Close(const std::filesystem::path& session_dir);

 private:
  EventOutput(std::unique_ptr<bench::EventStream> stream, std::string target);
  std::unique_ptr<bench::EventStream> stream_;
  std::string target_;
  bench::SessionEventPublisher publisher_;
};

// The unit serial a session folder's session.json records ("" when it cannot be read): a resume's
// session_started event names the unit as the start did.
std::string RecordedSerial(const std::filesystem::path& session_dir);

}  // namespace hrgbench::app
