// The session report's speed and size on a production-size session (issue 9, section 2.8): 6 runs
// × 100 s × 1 kHz = 600 000 samples, the rate-table design of bench_configs/sim-ratetable.toml
// (δ, ξ, σ = 1e-4, seed 12345), simulated by the estimator's SimulateRuns and written with the
// session library. Prints a Markdown table: the median of 3 reports per row, each phase's time
// (reading, the re-run estimate, the page, gnuplot figures, the PDF) and the HTML's size.
//
//   report_benchmark [SESSION_DIR]     (default: the production session in a temporary directory)

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <unistd.h>
#include <filesystem>
#include <string>
#include <vector>

#include "hrgbench/estimator/simulation.hpp"
#include "hrgbench/report/session_report.hpp"
#include "hrgbench/session/session.hpp"

namespace {

namespace fs = std::filesystem;
using namespace hrgbench;

bool WriteProductionSession(const fs::path& dir) {
  const double omegas[] = {0.1, -0.1, 0.3, -0.3, 1.0, -1.0};
  const double bs[] = {0.0, 0.1, 0.2, 0.0, 0.1, 0.2};
  std::vector<estimator::RunPlan> plans;
  for (int k = 0; k < 6; ++k) {
    estimator::RunPlan p;
    p.omega_rad_s = omegas[k];
    p.b = bs[k];
    p.theta_rad = k * M_PI / 12.0;
    p.sample_rate_hz = 1000.0;
    p.duration_s = 100.0;
    plans.push_back(p);
  }
  estimator::SimulationOptions truth;
  truth.delta << -0.0008, 0.31, -1e-6, 2e-6, -3e-6, 1e-6;
  truth.xi << -0.005, 0.002, -0.004, 0.007;
  truth.sigma = 1e-4;
  truth.seed = 12345;
  const std::vector<estimator::RunData> runs = estimator::SimulateRuns(plans, truth);
  session::Session s;
  s.serial = "BENCH-report";
  s.sample_rate_hz = 1000.0;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    session::RunEntry entry;
    entry.id = static_cast<int>(k + 1);
    entry.file = "runs/run-00" + std::to_string(k + 1) + ".csv";
    entry.omega_rad_s = omegas[k];
    s.runs.push_back(entry);
    session::RunSamples samples;
    samples.t_s = runs[k].t_s;
    samples.y = runs[k].y;
    if (!session::WriteRunCsv(dir / entry.file, samples)) return false;
  }
  s.document = {{"simulation", {{"delta", std::vector<double>(truth.delta.begin(), truth.delta.end())},
                                {"xi", std::vector<double>(truth.xi.begin(), truth.xi.end())}}}};
  return static_cast<bool>(session::WriteSessionJson(dir, s));
}

}  // namespace

int main(int argc, char** argv) {
  fs::path dir;
  fs::path scratch;
  if (argc > 1) {
    dir = argv[1];
  } else {
    scratch = fs::temp_directory_path() / ("hrgbench_report_benchmark_" + std::to_string(::getpid()));
    dir = scratch;
    std::printf("writing the production session (600 000 samples) to %s ...\n", dir.c_str());
    if (!WriteProductionSession(dir)) {
      std::fprintf(stderr, "cannot write the session\n");
      return 1;
    }
  }
  struct Row {
    const char* name;
    bool figures, pdf;
  };
  const Row rows[] = {{"HTML + data", false, false},
                      {"+ gnuplot SVG figures", true, false},
                      {"+ PDF (Chromium)", false, true},
                      {"HTML + figures + PDF", true, true}};
  std::printf("\n| report | read s | estimate s | page s | figures s | PDF s | total s | HTML MB |\n"
              "|---|---|---|---|---|---|---|---|\n");
  int status = 0;
  for (const Row& row : rows) {
    std::vector<report::ReportResult> results;
    std::vector<double> totals;
    for (int i = 0; i < 3; ++i) {
      report::ReportOptions options;
      options.figures = row.figures;
      options.pdf = row.pdf;
      const auto start = std::chrono::steady_clock::now();
      auto result = report::WriteSessionReport(dir, options);
      totals.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      if (!result) {
        std::fprintf(stderr, "report failed: %s\n", result.error().ToString().c_str());
        return 1;
      }
      for (const std::string& w : result->warnings)
        if (w.find("figures") != std::string::npos || w.find("PDF") != std::string::npos) {
          std::fprintf(stderr, "warning: %s\n", w.c_str());
          status = 1;
        }
      results.push_back(*result);
    }
    // The run with the median total.
    std::vector<std::size_t> order = {0, 1, 2};
    std::sort(order.begin(), order.end(), [&](auto a, auto b) { return totals[a] < totals[b]; });
    const report::ReportResult& r = results[order[1]];
    std::printf("| %s | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.2f |\n", row.name, r.read_s,
                r.estimate_s, r.page_s, r.figures_s, r.pdf_s, totals[order[1]],
                static_cast<double>(r.html_bytes) / 1e6);
  }
  if (!scratch.empty()) {
    std::error_code ec;
    fs::remove_all(scratch, ec);
  }
  return status;
}
