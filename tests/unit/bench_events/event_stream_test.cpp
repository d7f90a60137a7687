// EventStream against real pipes: every line a JSON object with the stream's fields first and
// seq in order; a full queue drops (and counts) instead of waiting; a reader that stops or goes
// away costs events, never a blocked producer; Close always returns and ends with the "end" event.
#include "hrgbench/bench/events/event_stream.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>
#include <thread>
#include <vector>

namespace hrgbench::bench {
namespace {

struct Pipe {
  int read_fd = -1;
  int write_fd = -1;
  Pipe() {
    int fds[2];
    EXPECT_EQ(::pipe2(fds, O_CLOEXEC), 0);
    read_fd = fds[0];
    write_fd = fds[1];
  }
  ~Pipe() {
    if (read_fd >= 0) ::close(read_fd);
  }
};

// Everything readable until EOF (the writer closed its end).
std::string ReadAll(int fd) {
  std::string text;
  char buffer[4096];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n <= 0) break;
    text.append(buffer, static_cast<std::size_t>(n));
  }
  return text;
}

std::vector<nlohmann::json> Lines(const std::string& text) {
  std::vector<nlohmann::json> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    EXPECT_NE(end, std::string::npos) << "the last line is not terminated";
    if (end == std::string::npos) break;
    lines.push_back(nlohmann::json::parse(text.substr(start, end - start)));
    start = end + 1;
  }
  return lines;
}

class EventStreamTest : public ::testing::Test {
 protected:
  // A reader that went away must cost events, not the test process.
  void SetUp() override { ::signal(SIGPIPE, SIG_IGN); }
};

TEST_F(EventStreamTest, EveryEventALineInOrderThenEnd) {
  Pipe pipe;
  auto stream = EventStream::FromFd(pipe.write_fd, 64);
  for (int i = 0; i < 10; ++i) stream->Publish({{"type", "progress"}, {"samples", i}});
  const EventStreamStats stats = stream->Close(30'000);
  const std::vector<nlohmann::json> lines = Lines(ReadAll(pipe.read_fd));
  ASSERT_EQ(lines.size(), 11u);
  for (int i = 0; i < 10; ++i) {
    const nlohmann::json& e = lines[static_cast<std::size_t>(i)];
    EXPECT_EQ(e["v"], kEventFormatVersion);
    EXPECT_EQ(e["seq"], i);
    EXPECT_EQ(e["type"], "progress");
    EXPECT_EQ(e["samples"], i);
    EXPECT_TRUE(e["time_unix_s"].is_number());
  }
  EXPECT_EQ(lines[10]["type"], "end");
  EXPECT_EQ(lines[10]["seq"], 10);
  EXPECT_EQ(lines[10]["events_published"], 10);
  EXPECT_EQ(lines[10]["events_lost"], 0);
  EXPECT_EQ(stats.published, 10u);
  EXPECT_EQ(stats.written, 10u);
  EXPECT_EQ(stats.lost, 0u);
  EXPECT_TRUE(stats.end_written);
}

TEST_F(EventStreamTest, StreamFieldsComeFirstInAFixedOrder) {
  Pipe pipe;
  auto stream = EventStream::FromFd(pipe.write_fd, 4);
  stream->Publish({{"type", "log"}, {"message", "a"}, {"a_field", 1}});
  stream->Close(30'000);
  const std::string text = ReadAll(pipe.read_fd);
  // A reader may check version and order with a prefix match before it parses the rest.
  EXPECT_EQ(text.rfind("{\"v\":1,\"seq\":0,\"time_unix_s\":", 0), 0u) << text;
  const std::size_t type = text.find(",\"type\":\"log\",\"a_field\":1,\"message\":\"a\"}\n");
  EXPECT_NE(type, std::string::npos) << text;
}

TEST_F(EventStreamTest, UnencodableValuesBecomeValidJson) {
  Pipe pipe;
  auto stream = EventStream::FromFd(pipe.write_fd, 4);
  stream->Publish({{"type", "warning"},
                   {"message", std::string("bad \xff byte")},
                   {"x", std::numeric_limits<double>::quiet_NaN()}});
  stream->Publish(nlohmann::json::object());  // no type
  stream->Close(30'000);
  const std::vector<nlohmann::json> lines = Lines(ReadAll(pipe.read_fd));
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_TRUE(lines[0]["x"].is_null());  // JSON has no NaN
  EXPECT_EQ(lines[0]["message"], "bad \xEF\xBF\xBD byte");
  EXPECT_EQ(lines[1]["type"], "unknown");
}

TEST_F(EventStreamTest, AStoppedReaderCostsEventsNeverAWaitingProducer) {
  Pipe pipe;
  // The reader has stopped: the pipe is full before the first event.
  ASSERT_GT(::fcntl(pipe.write_fd, F_SETPIPE_SZ, 4096), 0);
  const int flags = ::fcntl(pipe.write_fd, F_GETFL);
  ASSERT_EQ(::fcntl(pipe.write_fd, F_SETFL, flags | O_NONBLOCK), 0);
  std::size_t filler = 0;
  const std::string block(512, 'x');
  for (;;) {
    const ssize_t n = ::write(pipe.write_fd, block.data(), block.size());
    if (n <= 0) break;
    filler += static_cast<std::size_t>(n);
  }
  ASSERT_EQ(::fcntl(pipe.write_fd, F_SETFL, flags), 0);  // the stream sees a blocking pipe

  constexpr std::size_t kCapacity = 8;
  constexpr int kEvents = 1000;
  auto stream = EventStream::FromFd(pipe.write_fd, kCapacity);
  // Would hang here (and the test time out) if Publish waited for the reader.
  for (int i = 0; i < kEvents; ++i) stream->Publish({{"type", "progress"}, {"samples", i}});
  const EventStreamStats before = stream->Stats();
  EXPECT_EQ(before.published, static_cast<std::uint64_t>(kEvents));
  // Nothing can have been written; at most the queue plus the writer's batch (each up to the
  // capacity) is held.
  EXPECT_EQ(before.written, 0u);
  EXPECT_GE(before.lost, static_cast<std::uint64_t>(kEvents) - 2 * kCapacity);
  // The reader never comes back: Close gives up after its drain time and says so.
  const EventStreamStats stats = stream->Close(200);
  EXPECT_EQ(stats.written + stats.lost, stats.published);
  EXPECT_EQ(stats.written, 0u);
  EXPECT_FALSE(stats.end_written);
  // Only the filler reached the pipe, and no partial line: the stream wrote nothing.
  EXPECT_EQ(ReadAll(pipe.read_fd).size(), filler);
}

// A reader slower than the session's end: the last event is half written when Close's drain time
// is up. It is finished (the reader is reading), and "end" follows it, instead of the stream
// stopping in the middle of a line with nothing after it parseable (issue 25 row 14).
TEST_F(EventStreamTest, ALineBegunBeforeTheDrainDeadlineIsFinishedAndEndFollows) {
  Pipe pipe;
  ASSERT_GT(::fcntl(pipe.write_fd, F_SETPIPE_SZ, 4096), 0);
  auto stream = EventStream::FromFd(pipe.write_fd, 8);
  stream->Publish({{"type", "estimate"}, {"text", std::string(16 * 1024, 'y')}});
  // Wait (hang guard: the test's timeout) until the writer has begun the line and filled the pipe.
  for (int queued = 0; queued < 4096;) {
    ASSERT_EQ(::ioctl(pipe.read_fd, FIONREAD, &queued), 0);
    if (queued < 4096) ::usleep(1000);
  }
  // Close with no drain time: its deadline has passed before the reader takes the first byte.
  EventStreamStats stats;
  std::thread closer([&] { stats = stream->Close(0); });
  const std::vector<nlohmann::json> lines = Lines(ReadAll(pipe.read_fd));
  closer.join();
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0]["type"], "estimate");
  EXPECT_EQ(lines[0]["text"].get<std::string>().size(), 16u * 1024);
  EXPECT_EQ(lines[1]["type"], "end");
  EXPECT_TRUE(stats.end_written);
  EXPECT_EQ(stats.written, 1u);
  EXPECT_TRUE(stats.write_error.empty()) << stats.write_error;
}

TEST_F(EventStreamTest, ASlowReaderSeesGapsInSeqAndTheCountAtTheEnd) {
  Pipe pipe;
  auto stream = EventStream::FromFd(pipe.write_fd, 2);
  // Nobody reads while these are published: the pipe takes them all (64 kB), but the queue of 2
  // may overflow while the writer is between batches, depending on scheduling. Whatever was lost
  // is a gap in seq and counted in "end".
  for (int i = 0; i < 200; ++i) stream->Publish({{"type", "progress"}, {"i", i}});
  const EventStreamStats stats = stream->Close(30'000);
  const std::vector<nlohmann::json> lines = Lines(ReadAll(pipe.read_fd));
  ASSERT_FALSE(lines.empty());
  const nlohmann::json& end = lines.back();
  ASSERT_EQ(end["type"], "end");
  std::uint64_t previous = 0;
  for (std::size_t i = 0; i + 1 < lines.size(); ++i) {
    const std::uint64_t seq = lines[i]["seq"];
    if (i > 0) {
      EXPECT_GT(seq, previous);
    }
    EXPECT_EQ(lines[i]["i"], seq);  // the event that was published with that number
    previous = seq;
  }
  EXPECT_EQ(lines.size() - 1 + static_cast<std::size_t>(end["events_lost"]), 200u);
  EXPECT_EQ(end["events_lost"], stats.lost);
  EXPECT_EQ(end["seq"], 200);
}

TEST_F(EventStreamTest, AGoneReaderIsAWriteErrorAndEveryEventLost) {
  Pipe pipe;
  ::close(pipe.read_fd);
  pipe.read_fd = -1;
  auto stream = EventStream::FromFd(pipe.write_fd, 16);
  for (int i = 0; i < 5; ++i) stream->Publish({{"type", "log"}, {"message", "x"}});
  const EventStreamStats stats = stream->Close(30'000);
  EXPECT_EQ(stats.published, 5u);
  EXPECT_EQ(stats.lost, 5u);
  EXPECT_EQ(stats.written, 0u);
  EXPECT_FALSE(stats.end_written);
  EXPECT_FALSE(stats.write_error.empty());
}

TEST_F(EventStreamTest, PublishAfterCloseIsCountedLost) {
  Pipe pipe;
  auto stream = EventStream::FromFd(pipe.write_fd, 4);
  stream->Close(30'000);
  stream->Publish({{"type", "log"}});
  const EventStreamStats stats = stream->Stats();
  EXPECT_EQ(stats.published, 1u);
  EXPECT_EQ(stats.lost, 1u);
  EXPECT_EQ(Lines(ReadAll(pipe.read_fd)).size(), 1u);  // the end event only
}

TEST_F(EventStreamTest, OpenNamesTheFileThatCannotBeOpened) {
  auto opened = EventStream::Open("/nonexistent-dir/events.jsonl", 4);
  ASSERT_FALSE(opened);
  EXPECT_NE(opened.error().find("/nonexistent-dir/events.jsonl"), std::string::npos);
}

// A fresh path in the test's temporary folder.
std::string TempPath(const std::string& name) {
  char dir[] = "/tmp/hrgbench-events-XXXXXX";
  EXPECT_NE(::mkdtemp(dir), nullptr);
  return std::string(dir) + "/" + name;
}

std::string FileText(const std::string& path) {
  std::string text;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return text;
  text = ReadAll(fd);
  ::close(fd);
  return text;
}

// Issue 25 row 9: a FIFO nobody reads yet is refused at once with what to do; it used to block
// the open forever. The open runs in a child so a regression is a failure, not a hung suite.
TEST_F(EventStreamTest, AFifoWithoutAReaderIsRefusedAtOnce) {
  const std::string fifo = TempPath("events.fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  Pipe report;
  const pid_t child = ::fork();
  if (child == 0) {
    auto opened = EventStream::Open(fifo, 4);
    const std::string text = opened ? "opened" : opened.error();
    (void)!::write(report.write_fd, text.data(), text.size());
    std::_Exit(0);
  }
  ::close(report.write_fd);
  // A hang guard, not a timing assertion: the refusal is immediate.
  int status = 0;
  pid_t done = 0;
  for (int i = 0; i < 300 && done == 0; ++i) {
    done = ::waitpid(child, &status, WNOHANG);
    if (done == 0) ::usleep(100'000);
  }
  if (done == 0) {
    ::kill(child, SIGKILL);
    ::waitpid(child, &status, 0);
    FAIL() << "--events on a FIFO without a reader blocked for 30 s";
  }
  const std::string text = ReadAll(report.read_fd);
  EXPECT_NE(text.find("no reader"), std::string::npos) << text;
  EXPECT_NE(text.find(fifo), std::string::npos) << text;
  // With a reader it opens, and the reader gets the stream.
  const int reader = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  ASSERT_GE(reader, 0);
  auto opened = EventStream::Open(fifo, 4);
  ASSERT_TRUE(opened) << opened.error();
  (*opened)->Publish({{"type", "log"}, {"message", "x"}});
  (*opened)->Close(30'000);
  ::fcntl(reader, F_SETFL, 0);
  EXPECT_EQ(Lines(ReadAll(reader)).size(), 2u);
  ::close(reader);
}

// Issue 25 row 9: an existing file that is not an event stream (another session's session.json)
// is refused and left as it was; an earlier event stream or an empty file is replaced.
TEST_F(EventStreamTest, AnExistingFileThatIsNotAnEventStreamIsNeverTruncated) {
  const std::string record = TempPath("session.json");
  const std::string text = "{\n  \"state\": \"closed\"\n}\n";
  {
    const int fd = ::open(record.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
    ASSERT_EQ(::write(fd, text.data(), text.size()), static_cast<ssize_t>(text.size()));
    ::close(fd);
  }
  auto refused = EventStream::Open(record, 4);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().find("not an event stream"), std::string::npos) << refused.error();
  EXPECT_EQ(FileText(record), text);

  const std::string earlier = TempPath("events.jsonl");
  for (int round = 0; round < 2; ++round) {
    auto opened = EventStream::Open(earlier, 4);
    ASSERT_TRUE(opened) << opened.error();
    (*opened)->Publish({{"type", "log"}, {"message", "round " + std::to_string(round)}});
    (*opened)->Close(30'000);
  }
  const std::vector<nlohmann::json> lines = Lines(FileText(earlier));
  ASSERT_EQ(lines.size(), 2u);  // the second stream replaced the first (its event, then "end")
  EXPECT_EQ(lines[0].value("message", ""), "round 1") << lines[0].dump();
}

}  // namespace
}  // namespace hrgbench::bench
