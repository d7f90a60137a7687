// hrg-report SESSION_DIR: the session report (HTML, SVG figures, PDF); see
// include/hrgbench/report/session_report.hpp.

// GCC 12 at -O2 reports a "potential null pointer dereference" inside CLI11's detail::split
// (std::vector<std::string> relocation) as inlined here since SESSION_DIR became a list: a false
// positive in library code, as in hrg_results_main.cpp.
#pragma GCC diagnostic ignored "-Wnull-dereference"
#include <spdlog/spdlog.h>
#include <sys/resource.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstring>
#include <expected>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "app/cli_exit.hpp"
#include "app/logging.hpp"
#include "app/memory_policy.hpp"
#include "app/report_job.hpp"
#include "app/unit_history.hpp"
#include "app/utc_now.hpp"
#include "hrgbench/config/station_config.hpp"
#include "hrgbench/report/session_report.hpp"
#include "hrgbench/session/kill_point.hpp"

namespace {

using namespace hrgbench;

struct Arguments {
  std::vector<std::string> dirs;
  bool job = false;
  int job_start_fd = -1;
  std::string output;
  bool no_pdf = false;
  std::string paper;  // empty: the session's station's [report] paper, else A4
  bool no_figures = false;
  bool refit = false;
  std::string chart_js;
  std::string results_url;
};

// The PDF's sheet: --paper; else what the session's station declared ([report] paper in its copy
// config/station.toml, so a report regenerated later prints as the station did); else A4.
report::PaperSize Paper(const Arguments& args, const std::string& dir) {
  if (!args.paper.empty()) return *report::ParsePaperSize(args.paper);  // CLI11 checked it
  const std::filesystem::path copy = std::filesystem::path(dir) / "config" / "station.toml";
  std::error_code ec;
  if (!std::filesystem::exists(copy, ec)) return report::PaperSize::kA4;
  const auto station = bench::LoadStationConfig(copy);
  if (!station) {
    spdlog::warn("{}; the PDF is printed on A4", station.error().ToString());
    return report::PaperSize::kA4;
  }
  return report::ParsePaperSize(station->report_paper).value_or(report::PaperSize::kA4);
}

// One session's report; its files, or the reason it was not written (on stderr too).
std::expected<std::vector<std::string>, std::string> WriteOne(const Arguments& args,
                                                              const std::string& dir) {
  report::ReportOptions options;
  options.output = args.output;
  options.pdf = !args.no_pdf;
  options.paper = Paper(args, dir);
  options.figures = !args.no_figures;
  options.refit = args.refit;
  options.chart_js = args.chart_js;
  options.unit_history = app::ReadUnitHistory(args.results_url, dir);
  const auto written = report::WriteSessionReport(dir, options);
  if (!written) {
    // The message alone on stderr, so scripts can match it (it names the file and field).
    std::cerr << written.error().ToString() << '\n';
    return std::unexpected(written.error().ToString());
  }
  for (const std::string& w : written->warnings) spdlog::warn("{}", w);
  std::vector<std::string> files{written->html.string()};
  if (!written->pdf.empty()) files.push_back(written->pdf.string());
  for (const auto& f : written->figures) files.push_back(f.string());
  for (const std::string& f : files) std::cout << f << '\n';
  return files;
}

// --job: each session's report/job.json follows the report (report_job.hpp), and the job gives
// way to the station's own work (nice 10).
void RecordJob(const std::string& dir, app::ReportJob job) {
  if (auto written = app::WriteReportJob(dir, job); !written)
    spdlog::error("report job: {}", written.error());
}

int Run(const Arguments& args) {
  if (!args.output.empty() && args.dirs.size() != 1) {
    std::cerr << "-o/--output: names one session's report; give one SESSION_DIR\n";
    return kExitBadInput;
  }
  if (args.job_start_fd >= 0) {
    // The starter closes its end once every job.json says "running" (app/report_job.cpp).
    char byte;
    while (::read(args.job_start_fd, &byte, 1) > 0 || errno == EINTR) {
    }
    ::close(args.job_start_fd);
  }
  if (args.job && ::setpriority(PRIO_PROCESS, 0, 10) != 0)
    spdlog::warn("report job: cannot lower its priority: {}", std::strerror(errno));
  int code = kExitOk;
  for (const std::string& dir : args.dirs) {
    app::ReportJob job;
    job.pid = ::getpid();
    job.started = app::UtcNowText();
    if (args.job) {
      // Where the starter sent this job's output (app/report_job.cpp), kept.
      if (auto started = app::ReadReportJob(dir); started && *started) job.log = (*started)->log;
      RecordJob(dir, job);
      session::KillPoint("report.job");
    }
    std::expected<std::vector<std::string>, std::string> files;
    try {
      files = WriteOne(args, dir);
    } catch (const std::exception& error) {
      files = std::unexpected(std::string("the report failed: ") + error.what());
      std::cerr << files.error() << '\n';
    }
    if (!files) code = kExitBadInput;
    if (!args.job) continue;
    job.ended = app::UtcNowText();
    if (files) {
      job.state = app::ReportJobState::kWritten;
      job.files = std::move(*files);
    } else {
      job.state = app::ReportJobState::kFailed;
      job.reason = files.error();
    }
    RecordJob(dir, std::move(job));
  }
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  hrgbench::app::KeepFreedMemoryForReuse();  // first: before any thread
  CLI::App cli{
      "hrg-report: the session report. Reads SESSION_DIR (several: each in turn), draws the "
      "recorded fit (the estimate "
      "of record and each run's fitted state; a record from before they were kept has its "
      "estimate re-run, ml as the bench does, with a warning) and writes one self-contained HTML "
      "page (default SESSION_DIR/report/report.html; "
      "Chart.js from Debian's libjs-chart.js inlined, nothing fetched), every figure as SVG "
      "(gnuplot) and report.pdf (headless Chromium; HRGBENCH_CHROMIUM overrides the binary). A "
      "missing gnuplot or Chromium is a warning. Prints the files written, one per line.\n"
      "Here 0: written; 4: session.json unreadable, Chart.js missing (the reason on stderr, "
      "nothing written; with several sessions, the others are still written).\n" +
      std::string(hrgbench::kExitCodesHelp)};
  Arguments args;
  bool quiet = false;
  cli.add_option("dirs", args.dirs, "session directories (session.json + runs/), each in turn")
      ->required();
  cli.add_option("-o,--output", args.output,
                 "the HTML file (default SESSION_DIR/report/report.html)");
  cli.add_flag("--no-pdf", args.no_pdf, "do not print the PDF");
  cli.add_option("--paper", args.paper,
                 "the PDF's sheet: a4 or letter (default: the session's station's [report] paper, "
                 "else a4)")
      ->check(CLI::IsMember({"a4", "letter"}));
  cli.add_flag("--no-figures", args.no_figures, "do not draw the SVG figures");
  cli.add_flag("--refit", args.refit,
               "re-run the estimate (ml, as the bench does) and draw that fit instead of the "
               "recorded one; a warning names any component that differs from the record");
  cli.add_option("--chart-js", args.chart_js,
                 "Chart.js UMD build to inline (default: Debian's, "
                 "/usr/share/javascript/chart.js/chart.min.js)");
  cli.add_option("--results", args.results_url,
                 "results store (sqlite:PATH or postgresql://...): list the unit's earlier "
                 "sessions from it, as hrg-bench does for a station with [results] url");
  cli.add_flag("--job", args.job,
               "a report job (hrg-bench --report background starts one): each session's "
               "report/job.json says running, then written (its files) or failed (why); the job "
               "runs at nice 10");
  cli.add_option("--job-start-fd", args.job_start_fd,
                 "with --job: wait for end-of-file on this descriptor before starting (how "
                 "hrg-bench hands the job its go)")
      ->check(CLI::Range(3, 1023));
  hrgbench::app::AddCommonFlags(cli, &quiet);
  return hrgbench::app::ParseAndRun(cli, argc, argv, "hrg-report", quiet,
                                    [&] { return Run(args); });
}
