#include "app/closed_session_report.hpp"

#include <spdlog/spdlog.h>

#include <exception>
#include <system_error>

#include "app/unit_history.hpp"
#include "hrgbench/report/session_report.hpp"
#include "hrgbench/session/kill_point.hpp"

namespace hrgbench::app {
namespace {

namespace fs = std::filesystem;

bool HasRecord(const bench::SessionResult& result) {
  std::error_code ec;
  return !result.dir.empty() && fs::exists(result.dir / "session.json", ec);
}

// The session report (HTML, figures, PDF) into the closed session's folder, here and now. Empty
// when none was written. The store's history excludes the session itself (by its id), so the
// order of the report and the upload does not matter to it.
std::string WriteReport(const bench::SessionResult& result, const std::string& results_url,
                        const std::string& paper) {
  if (!HasRecord(result)) return {};
  session::KillPoint("report");
  try {
    report::ReportOptions options;
    options.unit_history = ReadUnitHistory(results_url, result.dir);
    options.paper = report::ParsePaperSize(paper).value_or(report::PaperSize::kA4);
    const auto written = report::WriteSessionReport(result.dir, options);
    if (!written) {
      spdlog::error("session report not written: {}", written.error().ToString());
      return {};
    }
    for (const std::string& w : written->warnings) spdlog::warn("report: {}", w);
    return written->html.string();
  } catch (const std::exception& error) {
    // The session is closed and its outcome decided: nothing the report does may change that.
    spdlog::error("session report not written: {}", error.what());
    return {};
  }
}

fs::path ReportHtml(const fs::path& dir) { return dir / "report" / "report.html"; }

}  // namespace

std::vector<ClosedReport> MakeReports(const std::vector<bench::SessionResult>& results,
                                      const std::string& results_url, const std::string& paper,
                                      ReportMode mode) {
  std::vector<ClosedReport> reports(results.size());
  if (mode == ReportMode::kNone) return reports;
  if (mode == ReportMode::kBackground) {
    std::vector<fs::path> dirs;
    for (const bench::SessionResult& result : results)
      if (HasRecord(result)) dirs.push_back(result.dir);
    if (dirs.empty()) return reports;
    // One unit's log beside its report; a fixture's in the fixture's folder.
    const fs::path log = dirs.size() == 1 ? dirs.front() / "report" / "job.log"
                                          : dirs.front().parent_path() / "report-job.log";
    session::KillPoint("report");
    if (auto job = StartReportJob(dirs, results_url, log)) {
      spdlog::info("report: being written by job {} (its state: {})", *job,
                   ReportJobFile(dirs.front()).string());
      for (std::size_t i = 0; i < results.size(); ++i) {
        if (!HasRecord(results[i])) continue;
        reports[i].path = ReportHtml(results[i].dir).string();
        reports[i].job = *job;
      }
      return reports;
    } else {
      spdlog::warn("{}; the report is written now", job.error());
    }
  }
  for (std::size_t i = 0; i < results.size(); ++i)
    reports[i].path = WriteReport(results[i], results_url, paper);
  return reports;
}

ClosedReport FinishReport(const bench::SessionResult& result, const std::string& results_url,
                          const std::string& paper, ReportMode mode) {
  std::error_code ec;
  if (fs::exists(ReportHtml(result.dir), ec)) return {ReportHtml(result.dir).string(), {}};
  if (auto job = ReadReportJob(result.dir);
      job && *job && (*job)->state == ReportJobState::kRunning)
    return {ReportHtml(result.dir).string(), (*job)->pid};
  return MakeReports({result}, results_url, paper, mode).front();
}

}  // namespace hrgbench::app
