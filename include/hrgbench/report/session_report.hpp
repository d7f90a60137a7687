#pragma once
// hrg-report: the session report. One self-contained HTML file per session directory, readable
// offline (every script and style inlined, no http(s) URL anywhere in the file), plus optional
// gnuplot figures and a PDF printed by headless Chromium.
//
// What it does: reads the session (session::ReadSessionRecord, the one reader of the record; a run
// whose file is missing or empty is reported and left out), draws the fitted model of every run
// from the estimate of record (δ, ξ and each run's nuisance, outcome.estimate.fitted_runs, through
// estimator::FittedState), and writes the page. It does not re-run the estimate unless asked
// (ReportOptions::refit, hrg-report --refit), or the record keeps no fitted runs (a session
// recorded before they were kept, or one without an outcome such as hrg-sim's): then it re-runs it
// exactly as the bench does (bench::RunMethod, method "ml", the fit-quality limits the record holds
// under outcome.estimate.fit.limits) and a warning says so. Everything the page shows about the
// outcome, the verdict and the engineering quantities is taken from session.json; what the report
// computes itself (a re-run fit, the Cramér–Rao bound of the session's own design, the anisotropy
// axes when the record has no engineering list, sample-time jitter) is
// marked as derived (see the contract below).
//
// ## The HTML contract (the browser test, branch `browser`, relies on it; keep it exactly)
//  - Every chart is a `<canvas data-figure="NAME">` inside a `<figure>` with a `<figcaption>`.
//    Names: `channels-run-N`, `motion-run-N`, `residuals-run-N`, `residual-histogram-run-N`,
//    `residual-spectrum-run-N` (what the fit left: its density against N(0, σ̂²), its Welch PSD
//    against 2σ̂²/fs; only where the run has a fitted model), `orbit-run-N`, `forms-run-N`
//    (N = the run id; for every run when there are at most max_runs_with_figures, else for that
//    many, and the page has a run list `<section id="run-list">` with one row per run),
//    `anisotropy`, `std-vs-bound`; for a tuned unit (a tune.json beside session.json, written by
//    `hrg-bench tune`), in `<section id="tuning">`: `tune-rate-error-before`,
//    `tune-rate-error-after`, `tune-scale-factor` and, after a zero-rate hold, `tune-allan`.
//  - When every chart has been drawn the page sets
//    `document.documentElement.dataset.reportReady = "true"`.
//  - Every number shown in a table is an element with `data-source="<JSON pointer into
//    session.json, RFC 6901>"` (e.g. `/outcome/estimate/delta/1`) and `data-value="<the value,
//    shortest round-trip>"`, its text being that value formatted for reading; a std is its own
//    element with its own data-source (e.g. `/outcome/estimate/delta_std/1`).
//    Numbers the report computes itself (not in session.json) carry `data-derived="<JSON pointer
//    into the report-data block>"` instead of data-source, and data-value likewise; numbers of
//    the tuning's record carry `data-tune-source="<JSON pointer into tune.json>"`.
//  - Every warning is `<li class="warning" data-run="N">` inside run N's section
//    (`<section class="run" id="run-N" data-run="N">`), or at the top with data-run="0" for
//    warnings of the whole session (and for a run id that session.json does not list).
//  - The outcome is `<div id="outcome" data-kind="KIND">`, KIND = outcome.kind as recorded
//    ("PASS", "FAIL", "ERROR", ...) or "NOT RECORDED" when session.json has no outcome; a tuned
//    unit's tuning verdict is `<div id="tune-outcome" data-kind="KIND">` (tune.json's
//    verdict.outcome). A tune.json that cannot be read (bounds: 4 MiB, 16 levels; format
//    "hrgbench-tune", version 1) is a warning and no section, never a failure.
//  - The page's data is one `<script type="application/json" id="report-data">` block.
//
// Files: <output> (default SESSION_DIR/report/report.html); beside it, unless disabled,
// report.pdf and the figures <name>.svg. Each file is written atomically
// (session::WriteFileAtomic). External programs (gnuplot, chromium) run as subprocesses with their
// input in temporary files; a missing or failing program is a warning in the result (and in the
// page for gnuplot), never a failure of the report.
//
// Threads: WriteSessionReport may be called from any thread; it starts the estimator's threads and
// child processes and waits for them. Never throws except std::bad_alloc.

#include <cstddef>
#include <expected>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hrgbench::report {

// The unit's other sessions, from the station's results store (results/results_store.hpp). The
// caller queries the store; the report opens no database.
struct UnitHistoryEntry {
  std::string started_utc;
  std::string station;
  std::string outcome;  // PASS, FAIL, ERROR, ABORTED
  std::string path;     // the session folder as stored
  // Engineering quantities by name (estimator/engineering_quantities.hpp: "tau_s", "q_factor",
  // ...); a quantity the session did not determine is absent.
  std::map<std::string, double> values;
  // Their standard uncertainties as stored (a quantity without one is absent): the trend plots'
  // bars.
  std::map<std::string, double> stds;
};
struct UnitHistory {
  std::string store;                       // where it came from (the URL without its password)
  std::vector<UnitHistoryEntry> sessions;  // oldest first, this session excluded
  std::string unavailable;                 // non-empty: the store could not be read, and why
};
// The most earlier sessions the page lists (the newest ones; the count says how many there are).
inline constexpr std::size_t kMaxUnitHistoryRows = 50;

// The PDF's sheet. A4 (ISO 216) unless the station or the command says otherwise; US Letter for
// lines that file on it.
enum class PaperSize { kA4, kLetter };
std::string_view ToString(PaperSize paper) noexcept;  // "a4", "letter"
std::optional<PaperSize> ParsePaperSize(std::string_view text) noexcept;

struct ReportOptions {
  // The HTML file; empty = <session>/report/report.html. Figures and the PDF go beside it.
  std::filesystem::path output;
  bool pdf = true;  // print the page to report.pdf with headless Chromium
  PaperSize paper = PaperSize::kA4;
  bool figures = true;  // draw every figure as SVG with gnuplot
  // Chart.js UMD build to inline; empty = the first of kChartJsCandidates that exists.
  std::filesystem::path chart_js;
  // Chromium binary; empty = $HRGBENCH_CHROMIUM, else "chromium" on PATH.
  std::string chromium;
  // Points per series on the page (min/max per bucket, see decimate.hpp). 2000 keeps a production
  // session (6 runs × 100 000 samples) under 5 MB of HTML.
  std::size_t max_points_per_series = 2000;
  // Runs drawn with their seven figures. A session with more runs gets a run list (one row per
  // run) and the figures of this many: the first, the last and those with the largest residual
  // RMS. Each run with figures adds ≈ 0.6 MB to the page at 2000 points per series, each run
  // without ≈ 3 kB, so the page stays under ≈ 12 MB at the sequence bound of 1000 runs
  // (docs/panel/report.md "Size and memory").
  std::size_t max_runs_with_figures = 12;
  // Seconds a child process (gnuplot, chromium) may take before it is killed.
  double child_timeout_s = 60.0;
  // The unit's earlier sessions (section "unit-history"); nullopt: no store configured, no section.
  std::optional<UnitHistory> unit_history;
  // Re-run the estimate even when the record keeps the fitted runs (to check the recorded fit, or
  // to draw it with this build's estimator). Off: the recorded fit is drawn.
  bool refit = false;
};

// Where Debian's libjs-chart.js puts its UMD build (chart.min.js is the UMD bundle in 3.x; the
// .mjs/.esm files are ES modules and cannot be inlined as a classic script).
inline constexpr const char* kChartJsCandidates[] = {
    "/usr/share/javascript/chart.js/chart.umd.min.js",
    "/usr/share/javascript/chart.js/chart.min.js",
    "/usr/share/javascript/chart.js/chart.umd.js",
    "/usr/share/javascript/chart.js/chart.js",
};

struct ReportError {
  std::filesystem::path file;  // the file at fault
  std::string field;           // JSON key path or CSV column; empty when not about one
  std::string message;

  std::string ToString() const;  // "<file>: field '<field>': <message>"
};

struct ReportResult {
  std::filesystem::path html;  // written
  std::filesystem::path pdf;   // empty when not written
  std::vector<std::filesystem::path> figures;
  std::size_t html_bytes = 0;
  // Everything the page lists as a warning, and what went wrong with the PDF (not in the page).
  std::vector<std::string> warnings;
  // Seconds spent: reading the session, the estimate, building and writing the page, the gnuplot
  // figures, the PDF.
  double read_s = 0.0, estimate_s = 0.0, page_s = 0.0, figures_s = 0.0, pdf_s = 0.0;
  // The estimator ran (ReportOptions::refit, or a record without fitted runs); false: the fit
  // drawn is the recorded one.
  bool estimate_rerun = false;
};

// Refuses (ReportError, nothing written) when session.json cannot be read or is not a session
// (the error names the file and field), or when Chart.js is missing; everything else the session
// lacks (run files, an outcome, an estimate, engineering quantities, a verdict) is said in the
// page.
std::expected<ReportResult, ReportError> WriteSessionReport(
    const std::filesystem::path& session_dir, const ReportOptions& options = {});

}  // namespace hrgbench::report
