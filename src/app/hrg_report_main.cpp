// hrg-report SESSION_DIR: the session report (HTML, SVG figures, PDF); see
// include/hrgbench/report/session_report.hpp.

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>
#include <string>

#include "app/cli_exit.hpp"
#include "app/logging.hpp"
#include "app/memory_policy.hpp"
#include "app/unit_history.hpp"
#include "hrgbench/config/station_config.hpp"
#include "hrgbench/report/session_report.hpp"

namespace {

using namespace hrgbench;

struct Arguments {
  std::string dir;
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
report::PaperSize Paper(const Arguments& args) {
  if (!args.paper.empty()) return *report::ParsePaperSize(args.paper);  // CLI11 checked it
  const std::filesystem::path copy = std::filesystem::path(args.dir) / "config" / "station.toml";
  std::error_code ec;
  if (!std::filesystem::exists(copy, ec)) return report::PaperSize::kA4;
  const auto station = bench::LoadStationConfig(copy);
  if (!station) {
    spdlog::warn("{}; the PDF is printed on A4", station.error().ToString());
    return report::PaperSize::kA4;
  }
  return report::ParsePaperSize(station->report_paper).value_or(report::PaperSize::kA4);
}

int Run(const Arguments& args) {
  report::ReportOptions options;
  options.output = args.output;
  options.pdf = !args.no_pdf;
  options.paper = Paper(args);
  options.figures = !args.no_figures;
  options.refit = args.refit;
  options.chart_js = args.chart_js;
  options.unit_history = app::ReadUnitHistory(args.results_url, args.dir);
  const auto written = report::WriteSessionReport(args.dir, options);
  if (!written) {
    // The message alone on stderr, so scripts can match it (it names the file and field).
    std::cerr << written.error().ToString() << '\n';
    return kExitBadInput;
  }
  for (const std::string& w : written->warnings) spdlog::warn("{}", w);
  std::cout << written->html.string() << '\n';
  if (!written->pdf.empty()) std::cout << written->pdf.string() << '\n';
  for (const auto& f : written->figures) std::cout << f.string() << '\n';
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  hrgbench::app::KeepFreedMemoryForReuse();  // first: before any thread
  CLI::App cli{
      "hrg-report: the session report. Reads SESSION_DIR, draws the recorded fit (the estimate "
      "of record and each run's fitted state; a record from before they were kept has its "
      "estimate re-run, ml as the bench does, with a warning) and writes one self-contained HTML "
      "page (default SESSION_DIR/report/report.html; "
      "Chart.js from Debian's libjs-chart.js inlined, nothing fetched), every figure as SVG "
      "(gnuplot) and report.pdf (headless Chromium; HRGBENCH_CHROMIUM overrides the binary). A "
      "missing gnuplot or Chromium is a warning. Prints the files written, one per line.\n"
      "Here 0: written; 4: session.json unreadable, Chart.js missing (the reason on stderr, "
      "nothing written).\n" +
      std::string(hrgbench::kExitCodesHelp)};
  Arguments args;
  bool quiet = false;
  cli.add_option("dir", args.dir, "session directory (session.json + runs/)")->required();
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
  hrgbench::app::AddCommonFlags(cli, &quiet);
  return hrgbench::app::ParseAndRun(cli, argc, argv, "hrg-report", quiet,
                                    [&] { return Run(args); });
}
