#pragma once
// A session's report written by a job of its own, off the session's critical path: `hrg-bench run
// --report background` closes the session, uploads it and exits; `hrg-report --job` (figures and
// Chromium's PDF: seconds) follows at a lower priority, in a process session of its own. The job's
// state is <session>/report/job.json:
//
//   {"format": "hrgbench-report-job", "version": 1,
//    "state": "running" | "written" | "failed", "pid": 1234,
//    "started": "2026-11-27T10:00:00Z", "ended": null | "...", "reason": null | "...",
//    "files": ["…/report/report.html", …], "log": "…/report/job.log"}
//
// A "running" job whose process is gone reads as interrupted (kill -9, a power cut): the report can
// be made again (`hrg-report SESSION`, or `hrg-bench resume SESSION`). docs/panel/report.md.

#include <sys/types.h>

#include <expected>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hrgbench::app {

enum class ReportJobState { kRunning, kWritten, kFailed, kInterrupted };
std::string_view ToString(ReportJobState state);

struct ReportJob {
  ReportJobState state = ReportJobState::kRunning;
  pid_t pid = 0;
  std::string started;  // UTC, ISO 8601
  std::string ended;    // empty while running
  std::string reason;   // failed or interrupted: why
  std::vector<std::string> files;
  std::string log;  // the job's output (its warnings, a failure's detail)
};

// What `hrg-bench run --report` does once the session is closed and uploaded.
enum class ReportMode {
  kWait,        // write it before exiting (the command line's default)
  kBackground,  // start a report job and exit (the panel's children)
  kNone,        // none (hrg-report SESSION makes it later)
};
std::optional<ReportMode> ParseReportMode(std::string_view text);

// <session>/report/job.json.
std::filesystem::path ReportJobFile(const std::filesystem::path& session_dir);

// Durably (a temporary, renamed): a reader sees the old state or the new, never a torn one.
std::expected<void, std::string> WriteReportJob(const std::filesystem::path& session_dir,
                                                const ReportJob& job);

// nullopt: the session has no job.json (no job was ever started for it). A "running" job whose
// process no longer runs hrg-report is returned as kInterrupted, with the reason. An unreadable,
// oversized or malformed file is an error naming the file and the field.
std::expected<std::optional<ReportJob>, std::string> ReadReportJob(
    const std::filesystem::path& session_dir);

// Starts `hrg-report --job SESSION...` (the hrg-report beside this program) for `session_dirs`, in
// turn, in a process session of its own (a Ctrl-C or a panel's stop of the bench does not reach
// it), no descriptor but its output inherited, its output in `log`. Each session's job.json says
// "running" with the job's pid before this returns. The job's pid, or why it was not started.
std::expected<pid_t, std::string> StartReportJob(
    const std::vector<std::filesystem::path>& session_dirs, const std::string& results_url,
    const std::filesystem::path& log);

}  // namespace hrgbench::app
