// kill -9 in the middle of run 3: the directory reads as a valid session with runs 1 and 2, and
// OpenForResume continues it with run 3.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>

#include "candump_log_parser.hpp"
#include "record_test_dir.hpp"
#include "recorder_fixture.hpp"

namespace hrgbench::bench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using record_test::CompleteEnd;
using record_test::ExpectCompleteRuns;
using record_test::RecordRun;
using record_test::StartFor;

constexpr int kFramesBeforeKill = 250;

// Child: records runs 1 and 2, starts run 3, streams half of it and some CAN frames, tells the
// parent, then waits to be killed. Exit codes > 0 name the step that failed.
[[noreturn]] void RecordUntilKilled(const fs::path& dir, const SessionHeader& header,
                                    int ready_fd) {
  RecorderOptions options;
  options.flush_interval_ns = 0;  // what is appended is in the file (page cache) at once
  auto recorder = SessionRecorder::Create(dir, header, options);
  if (!recorder) ::_exit(10);
  for (int k = 0; k < kFramesBeforeKill; ++k) {
    hw::CanFrame frame;
    frame.id = 0x181;
    frame.length = 8;
    frame.data[0] = static_cast<std::uint8_t>(k);
    const LoggedCanFrame logged{1'700'000'000'000'000'000 + k * 1'000'000LL, frame};
    if (!recorder->AppendCanFrames(std::span(&logged, 1))) ::_exit(11);
    if (k == 0 && !RecordRun(*recorder, header.runs[0])) ::_exit(12);
    if (k == 100 && !RecordRun(*recorder, header.runs[1])) ::_exit(13);
    if (k == 200 && !recorder->BeginRun(3, StartFor(header.runs[2]))) ::_exit(14);
  }
  const auto data = testing::SyntheticSamples(3, record_test::kSamplesPerRun / 2, 1000.0);
  if (!recorder->AppendSamples(data)) ::_exit(15);
  const char ready = 'r';
  if (::write(ready_fd, &ready, 1) != 1) ::_exit(16);
  for (;;) ::pause();
}

TEST(RecorderCrash, KillDashNineMidRunLeavesTheCompletedRunsAndResumeFinishesTheSession) {
  testing::ScratchDir scratch("record_crash");
  const fs::path dir = scratch / "session";
  const SessionHeader header = testing::SyntheticHeader(3);

  int pipe_fds[2];
  ASSERT_EQ(::pipe(pipe_fds), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::close(pipe_fds[0]);
    RecordUntilKilled(dir, header, pipe_fds[1]);
  }
  ::close(pipe_fds[1]);
  char ready = 0;
  const ssize_t n = ::read(pipe_fds[0], &ready, 1);
  ::close(pipe_fds[0]);
  ASSERT_EQ(::kill(child, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_EQ(n, 1) << "child failed before run 3, exit status " << WEXITSTATUS(status);
  ASSERT_TRUE(WIFSIGNALED(status));

  // As the dead process left it: a valid session, runs 1 and 2 complete and exact.
  ExpectCompleteRuns(dir, header, {1, 2});
  {
    auto read = session::ReadSession(dir);
    ASSERT_TRUE(read.has_value());
    EXPECT_EQ(read->document["state"], "running");  // never closed
    EXPECT_EQ(read->document["runs"][2]["status"], "running");
    EXPECT_EQ(read->warnings.size(), 1u);  // "run 3 skipped"
  }
  EXPECT_TRUE(fs::exists(dir / "runs" / "run-003.csv.partial"));
  auto lines = testing::ReadCandumpLog((dir / "can" / "session.log").string());
  ASSERT_TRUE(lines.has_value());
  EXPECT_EQ(lines->size(), static_cast<std::size_t>(kFramesBeforeKill));

  // Resume: run 3 is what remains; its streamed half is kept aside.
  auto resumed = SessionRecorder::OpenForResume(dir);
  ASSERT_TRUE(resumed.has_value()) << resumed.error().ToString();
  EXPECT_EQ(resumed->CompleteRunIds(), (std::vector<int>{1, 2}));
  EXPECT_EQ(resumed->RemainingRunIds(), (std::vector<int>{3}));
  EXPECT_FALSE(fs::exists(dir / "runs" / "run-003.csv.partial"));
  ASSERT_TRUE(fs::exists(dir / "runs" / "run-003.csv.interrupted"));
  {
    auto partial = session::ReadRunCsv(dir / "runs" / "run-003.csv.interrupted");
    ASSERT_TRUE(partial.has_value()) << partial.error().ToString();
    EXPECT_EQ(partial->size(), record_test::kSamplesPerRun / 2);
  }
  hw::CanFrame frame;
  frame.id = 0x183;
  const LoggedCanFrame after{1'800'000'000'000'000'000, frame};
  ASSERT_TRUE(resumed->AppendCanFrames(std::span(&after, 1)).has_value());
  auto recorded = RecordRun(*resumed, header.runs[2]);
  ASSERT_TRUE(recorded.has_value()) << recorded.error().ToString();
  ASSERT_TRUE(resumed->Close({OutcomeKind::kPass, "", {}, {}, {}}).has_value());

  ExpectCompleteRuns(dir, header, {1, 2, 3});
  auto read = session::ReadSession(dir);
  ASSERT_TRUE(read.has_value());
  const json& doc = read->document;
  EXPECT_EQ(doc["state"], "closed");
  EXPECT_EQ(doc["outcome"]["kind"], "PASS");
  ASSERT_EQ(doc["resumed_at"].size(), 1u);
  EXPECT_EQ(doc["resumed_at"][0]["previous_state"], "running");
  EXPECT_EQ(doc["runs"][2]["attempts"][0]["status"], "interrupted");
  EXPECT_EQ(doc["runs"][2]["attempts"][0]["file"], "runs/run-003.csv.interrupted");
  EXPECT_EQ(doc["runs"][2]["attempts"][0]["start"]["release_t_ns"], 3000);
  lines = testing::ReadCandumpLog((dir / "can" / "session.log").string());
  ASSERT_TRUE(lines.has_value());
  ASSERT_EQ(lines->size(), static_cast<std::size_t>(kFramesBeforeKill + 1));
  EXPECT_EQ(lines->back().frame.id, 0x183u);
}

TEST(RecorderCrash, ResumingAClosedErrorSessionKeepsItsOutcome) {
  testing::ScratchDir scratch("record_resume_closed");
  const fs::path dir = scratch / "session";
  const SessionHeader header = testing::SyntheticHeader(2);
  {
    auto recorder = SessionRecorder::Create(dir, header);
    ASSERT_TRUE(recorder.has_value());
    ASSERT_TRUE(RecordRun(*recorder, header.runs[0]).has_value());
    ASSERT_TRUE(recorder->Close({OutcomeKind::kError, "Modbus timeout", {}, {}, {}}).has_value());
  }
  auto resumed = SessionRecorder::OpenForResume(dir);
  ASSERT_TRUE(resumed.has_value()) << resumed.error().ToString();
  EXPECT_EQ(resumed->RemainingRunIds(), std::vector<int>{2});
  ASSERT_TRUE(RecordRun(*resumed, header.runs[1]).has_value());
  ASSERT_TRUE(resumed->Close({OutcomeKind::kPass, "", {}, {}, {}}).has_value());
  auto read = session::ReadSession(dir);
  ASSERT_TRUE(read.has_value());
  EXPECT_EQ(read->document["resumed_at"][0]["previous_outcome"]["reason"], "Modbus timeout");
  EXPECT_EQ(read->document["outcome"]["kind"], "PASS");
}

}  // namespace
}  // namespace hrgbench::bench
