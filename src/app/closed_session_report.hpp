#pragma once
// A closed session's report, as `hrg-bench run|resume --report` asks: written before the program
// exits, started as a job of its own that follows it (app/report_job.hpp), or none. A report that
// cannot be made is logged; it never changes the session's outcome or exit code.

#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "app/report_job.hpp"
#include "hrgbench/bench/sequencer/sequencer.hpp"

namespace hrgbench::app {

struct ClosedReport {
  std::string path;          // report.html: written, or being written by `job`; empty: none
  std::optional<pid_t> job;  // the report job writing it
};

// The report of each closed session of `results` (one unit's, or a fixture's units'): written in
// turn here (kWait), by one job for all of them (kBackground; written here when the job cannot be
// started), or not at all (kNone). `results_url`: the store the reports list each unit's earlier
// sessions from; `paper`: the station's [report] paper. One entry per result, in order; a result
// without a session.json (refused before its folder was made) gets none.
std::vector<ClosedReport> MakeReports(const std::vector<bench::SessionResult>& results,
                                      const std::string& results_url, const std::string& paper,
                                      ReportMode mode);

// The report a kill left unmade for a session closed with a verdict: kept when report.html exists
// or a live job is still writing it, else made as `mode` says.
ClosedReport FinishReport(const bench::SessionResult& result, const std::string& results_url,
                          const std::string& paper, ReportMode mode);

}  // namespace hrgbench::app
