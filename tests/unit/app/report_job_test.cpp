// The report job's record (app/report_job.hpp): read as the docs write it, refused with the file
// and field named when it is not one, and a "running" job whose process is gone or runs another
// program (a reused pid) read as interrupted.

#include "app/report_job.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "record_test_dir.hpp"

extern char** environ;

namespace hrgbench::app {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;

void WriteJobJson(const fs::path& session, const std::string& text) {
  fs::create_directories(session / "report");
  std::ofstream(session / "report" / "job.json") << text;
}

std::string Job(const std::string& state, long pid, const std::string& extra = "") {
  return "{\"format\": \"hrgbench-report-job\", \"version\": 1, \"state\": \"" + state +
         "\", \"pid\": " + std::to_string(pid) + ", \"started\": \"2026-11-27T10:00:00Z\"" + extra +
         "}";
}

// A process whose program's file name is hrg-report (a link to sleep), as a live job's is.
pid_t StartFakeJob(const fs::path& dir) {
  const fs::path program = dir / "hrg-report";
  fs::create_symlink("/bin/sleep", program);
  std::string path = program.string(), seconds = "60";
  char* argv[] = {path.data(), seconds.data(), nullptr};
  pid_t pid = 0;
  if (::posix_spawn(&pid, path.c_str(), nullptr, nullptr, argv, environ) != 0) return 0;
  // Until exec has replaced the child's image, its cmdline is still this test's.
  for (int i = 0; i < 500; ++i) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/cmdline");
    std::string argv0;
    if (std::getline(in, argv0, '\0') && fs::path(argv0).filename() == "hrg-report") break;
    ::usleep(10'000);
  }
  return pid;
}

pid_t DeadPid() {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return pid;
}

TEST(ReportJob, NoJobFileIsNoJob) {
  ScratchDir dir("report_job_none");
  const auto job = ReadReportJob(dir.path());
  ASSERT_TRUE(job) << job.error();
  EXPECT_FALSE(job->has_value());
}

TEST(ReportJob, AWrittenJobIsReadWithItsFiles) {
  ScratchDir dir("report_job_written");
  WriteJobJson(dir.path(), Job("written", 1,
                               ", \"ended\": \"2026-11-27T10:00:09Z\", "
                               "\"files\": [\"a/report.html\", \"a/report.pdf\"], "
                               "\"log\": \"a/job.log\", \"reason\": null"));
  const auto job = ReadReportJob(dir.path());
  ASSERT_TRUE(job) << job.error();
  ASSERT_TRUE(job->has_value());
  EXPECT_EQ((*job)->state, ReportJobState::kWritten);
  EXPECT_EQ((*job)->ended, "2026-11-27T10:00:09Z");
  ASSERT_EQ((*job)->files.size(), 2u);
  EXPECT_EQ((*job)->files[1], "a/report.pdf");
  EXPECT_EQ((*job)->log, "a/job.log");
}

TEST(ReportJob, ARunningJobIsRunningWhileItsProcessRunsHrgReport) {
  ScratchDir dir("report_job_running");
  const pid_t pid = StartFakeJob(dir.path());
  ASSERT_GT(pid, 0);
  WriteJobJson(dir.path() / "s", Job("running", pid));
  const auto running = ReadReportJob(dir.path() / "s");
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(running && running->has_value());
  EXPECT_EQ((*running)->state, ReportJobState::kRunning);
  EXPECT_EQ((*running)->pid, pid);
  // Killed (kill -9, a power cut): the same record now reads as interrupted, and says so.
  const auto killed = ReadReportJob(dir.path() / "s");
  ASSERT_TRUE(killed && killed->has_value());
  EXPECT_EQ((*killed)->state, ReportJobState::kInterrupted);
  EXPECT_NE((*killed)->reason.find(std::to_string(pid)), std::string::npos) << (*killed)->reason;
}

TEST(ReportJob, ARunningJobWhosePidIsGoneOrReusedIsInterrupted) {
  ScratchDir dir("report_job_gone");
  WriteJobJson(dir.path() / "gone", Job("running", DeadPid()));
  WriteJobJson(dir.path() / "reused", Job("running", ::getpid()));  // this test, not hrg-report
  for (const char* session : {"gone", "reused"}) {
    const auto job = ReadReportJob(dir.path() / session);
    ASSERT_TRUE(job && job->has_value()) << session;
    EXPECT_EQ((*job)->state, ReportJobState::kInterrupted) << session;
  }
}

TEST(ReportJob, AMalformedRecordIsRefusedNamingTheFileAndField) {
  ScratchDir dir("report_job_bad");
  const std::string file = (dir.path() / "report" / "job.json").string();
  const auto refused = [&](const std::string& text, const std::string& field) {
    WriteJobJson(dir.path(), text);
    const auto job = ReadReportJob(dir.path());
    ASSERT_FALSE(job) << text;
    EXPECT_NE(job.error().find(file), std::string::npos) << job.error();
    EXPECT_NE(job.error().find(field), std::string::npos) << job.error();
  };
  refused("[1, 2]", "not a JSON object");
  refused("{\"format\": \"hrgbench-session\"}", "format");
  refused(Job("finished", 1), "state");
  refused(Job("written", -4), "pid");
  refused("{\"format\": \"hrgbench-report-job\", \"state\": \"written\", \"pid\": \"12\"}", "pid");
  refused(Job("written", 1, ", \"files\": \"report.html\""), "files");
  refused(Job("written", 1, ", \"reason\": 7"), "reason");
  refused(Job("written", 1, ", \"pad\": \"" + std::string(70 * 1024, 'x') + "\""), "bytes");
}

TEST(ReportJob, WhatIsWrittenIsReadBack) {
  ScratchDir dir("report_job_round_trip");
  ReportJob job;
  job.state = ReportJobState::kFailed;
  job.pid = 4242;
  job.started = "2026-11-27T10:00:00Z";
  job.ended = "2026-11-27T10:00:03Z";
  job.reason = "session.json: outcome: missing";
  job.log = "x/job.log";
  ASSERT_TRUE(WriteReportJob(dir.path(), job));
  const auto read = ReadReportJob(dir.path());
  ASSERT_TRUE(read && read->has_value());
  EXPECT_EQ((*read)->state, ReportJobState::kFailed);
  EXPECT_EQ((*read)->pid, 4242);
  EXPECT_EQ((*read)->reason, job.reason);
  EXPECT_EQ((*read)->ended, job.ended);
  EXPECT_EQ((*read)->log, job.log);
}

TEST(ReportJob, TheModesAreNamedAsOnTheCommandLine) {
  EXPECT_EQ(ParseReportMode("wait"), ReportMode::kWait);
  EXPECT_EQ(ParseReportMode("background"), ReportMode::kBackground);
  EXPECT_EQ(ParseReportMode("none"), ReportMode::kNone);
  EXPECT_FALSE(ParseReportMode("later"));
}

}  // namespace
}  // namespace hrgbench::app
