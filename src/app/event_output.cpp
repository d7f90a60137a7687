#include "app/event_output.hpp"

#include <spdlog/spdlog.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "hrgbench/session/session.hpp"

namespace hrgbench::app {

std::expected<std::unique_ptr<EventOutput>, std::string> EventOutput::Open(
    const std::string& target, std::size_t capacity) {
  auto stream = bench::EventStream::Open(target, capacity);
  if (!stream) return std::unexpected(stream.error());
  return std::unique_ptr<EventOutput>(new EventOutput(std::move(*stream), target));
}

EventOutput::EventOutput(std::unique_ptr<bench::EventStream> stream, std::string target)
    : stream_(std::move(stream)), target_(std::move(target)), publisher_(*stream_) {}

void EventOutput::Close(const std::filesystem::path& session_dir) {
  const bench::EventStreamStats stats = stream_->Close();
  if (stats.lost > 0)
    spdlog::warn("event stream: {} of {} events lost (the reader was slow or went away{})",
                 stats.lost, stats.published,
                 stats.write_error.empty() ? "" : ": " + stats.write_error);
  std::error_code ec;
  if (session_dir.empty() || !std::filesystem::is_directory(session_dir, ec)) return;
  const nlohmann::json account = {{"format_version", bench::kEventFormatVersion},
                                  {"target", target_},
                                  {"events_published", stats.published},
                                  {"events_written", stats.written},
                                  {"events_lost", stats.lost},
                                  {"end_written", stats.end_written},
                                  {"write_error", stats.write_error}};
  const std::filesystem::path file = session_dir / "events.json";
  std::ofstream out(file);
  out << account.dump(1) << '\n';
  if (!out) spdlog::error("event stream: cannot write {}", file.string());
}

std::string RecordedSerial(const std::filesystem::path& session_dir) {
  // The session reader's own bounds and checks on session.json; the run files are not needed.
  session::ReadOptions options;
  options.load_samples = false;
  auto session = session::ReadSession(session_dir, options);
  return session ? std::move(session->serial) : std::string();
}

}  // namespace hrgbench::app
