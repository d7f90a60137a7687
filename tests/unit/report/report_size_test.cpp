// The page's size does not grow with the number of runs beyond the figure session_report.hpp
// states (ReportOptions::max_runs_with_figures): 300 short runs give a page within 1.5 times that
// of 30 (main before: 10 times, every run's five figures drawn; 198 MB for 300 runs of 5 s), with
// the figures of at most max_runs_with_figures runs, every run in the run list and in its own
// section. The runs: SimulateRuns (closed-form model, seeded noise σ = 1e-4, seed 11), 1 s at
// 400 Hz each, Ω cycled over ±0.1, ±0.3, ±1 rad/s; no outcome, so the report re-runs the estimate
// (the path that holds every run's samples for the fit and then reads each again to draw it).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <regex>
#include <string>
#include <vector>

#include "hrgbench/estimator/simulation.hpp"
#include "hrgbench/report/session_report.hpp"
#include "hrgbench/session/session.hpp"
#include "record_test_dir.hpp"
#include "report_test_session.hpp"

namespace hrgbench::report {
namespace {

namespace fs = std::filesystem;
using testing_support::Fast;
using testing_support::Read;

void WriteManyRuns(const fs::path& dir, int count) {
  const double omegas[] = {0.1, -0.1, 0.3, -0.3, 1.0, -1.0};
  std::vector<estimator::RunPlan> plans;
  for (int k = 0; k < count; ++k) {
    estimator::RunPlan p;
    p.omega_rad_s = omegas[k % 6];
    p.b = 0.1;
    p.theta_rad = (k % 12) * std::numbers::pi / 12.0;
    p.sample_rate_hz = 400.0;
    p.duration_s = 1.0;
    plans.push_back(p);
  }
  estimator::SimulationOptions truth;
  truth.delta << -1e-3, 0.3, 2e-6, -1e-6, 3e-5, -2e-5;
  truth.xi << 0.01, -0.003, 0.002, 0.004;
  truth.sigma = 1e-4;
  truth.seed = 11;
  const std::vector<estimator::RunData> runs = estimator::SimulateRuns(plans, truth);
  session::Session s;
  s.serial = "TEST-MANY";
  s.sample_rate_hz = 400.0;
  for (int k = 0; k < count; ++k) {
    session::RunEntry entry;
    entry.id = k + 1;
    entry.file = "runs/run-" + std::to_string(k + 1) + ".csv";
    entry.omega_rad_s = omegas[k % 6];
    s.runs.push_back(entry);
    session::RunSamples samples;
    samples.t_s = runs[static_cast<std::size_t>(k)].t_s;
    samples.y = runs[static_cast<std::size_t>(k)].y;
    ASSERT_TRUE(session::WriteRunCsv(dir / entry.file, samples));
  }
  ASSERT_TRUE(session::WriteSessionJson(dir, s));
}

std::size_t Count(const std::string& text, const std::string& pattern) {
  const std::regex re(pattern);
  return static_cast<std::size_t>(
      std::distance(std::sregex_iterator(text.begin(), text.end(), re), std::sregex_iterator()));
}

TEST(ReportSize, BoundedInTheNumberOfRuns) {
  const ReportOptions options = Fast();
  std::size_t bytes[2] = {0, 0};
  const int counts[2] = {30, 300};
  for (int i = 0; i < 2; ++i) {
    hrgbench::testing::ScratchDir dir("report_size");
    WriteManyRuns(dir.path(), counts[i]);
    const auto written = WriteSessionReport(dir.path(), options);
    ASSERT_TRUE(written) << written.error().ToString();
    bytes[i] = written->html_bytes;
    const std::string html = Read(written->html);
    // The figures of at most max_runs_with_figures runs (five each), the first and the last
    // among them; every run has its section and its row in the run list.
    EXPECT_LE(Count(html, "data-figure=\"channels-run-"), options.max_runs_with_figures);
    EXPECT_EQ(Count(html, "data-figure=\"[a-z]+-run-"), 5 * options.max_runs_with_figures);
    EXPECT_NE(html.find("data-figure=\"channels-run-1\""), std::string::npos);
    EXPECT_NE(html.find("data-figure=\"channels-run-" + std::to_string(counts[i]) + "\""),
              std::string::npos);
    EXPECT_EQ(Count(html, "<section class=\"run\" id=\"run-"), static_cast<std::size_t>(counts[i]));
    EXPECT_EQ(Count(html, "<tr><td><a href=\"#run-"), static_cast<std::size_t>(counts[i]));
  }
  EXPECT_LT(static_cast<double>(bytes[1]), 1.5 * static_cast<double>(bytes[0]))
      << bytes[0] << " bytes for 30 runs, " << bytes[1] << " for 300";
}

// A session of at most max_runs_with_figures runs is drawn whole, as before.
TEST(ReportSize, FewRunsAllDrawn) {
  hrgbench::testing::ScratchDir dir("report_size_few");
  WriteManyRuns(dir.path(), 6);
  const auto written = WriteSessionReport(dir.path(), Fast());
  ASSERT_TRUE(written) << written.error().ToString();
  const std::string html = Read(written->html);
  EXPECT_EQ(Count(html, "data-figure=\"[a-z]+-run-"), 30u);
  EXPECT_EQ(html.find("id=\"run-list\""), std::string::npos);
}

}  // namespace
}  // namespace hrgbench::report
