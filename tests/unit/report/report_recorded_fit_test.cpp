// The report draws the recorded fit: for a session closed with an estimate of record that keeps its
// fitted runs, the estimator does not run (ReportResult::estimate_rerun), and what is drawn is the
// fit the bench made, to the bit (the same figures as a --refit of the same samples). A record
// from before the fitted runs were kept is re-run, with a warning that says so.

#include <gtest/gtest.h>

#include "hrgbench/analysis/recorded_estimate.hpp"
#include "hrgbench/estimator/fit_diagnostics.hpp"
#include "report_test_session.hpp"

namespace hrgbench::report {
namespace {

using namespace testing_support;

// Closes the session WriteSession made as the sequencer does: the estimate of record (with its
// fitted runs) under outcome.estimate. `keep_fitted_runs` false: as a bench before this change.
void CloseWithEstimateOfRecord(const fs::path& dir, bool keep_fitted_runs) {
  auto recorded = session::ReadSession(dir);
  ASSERT_TRUE(recorded.has_value()) << recorded.error().ToString();
  const auto record = session::ReadSessionRecord(dir);
  ASSERT_TRUE(record.has_value()) << record.error().ToString();
  bench::RecordedEstimate estimate =
      bench::EstimateRecordedSession(*recorded, *record, estimator::FitQualityLimits{});
  ASSERT_TRUE(estimate.method.summary.IsUsable()) << estimate.method.summary.message;
  if (!keep_fitted_runs) estimate.report.erase("fitted_runs");
  recorded->document["state"] = "closed";
  recorded->document["outcome"] = json{{"kind", "PASS"},
                                       {"exit_code", 0},
                                       {"reason", ""},
                                       {"failed_parameters", json::array()},
                                       {"estimate", estimate.report}};
  ASSERT_TRUE(session::WriteSessionJson(dir, *recorded).has_value());
}

bool AnyWarningWith(const std::vector<std::string>& warnings, const std::string& text) {
  for (const std::string& w : warnings)
    if (w.find(text) != std::string::npos) return true;
  return false;
}

TEST(ReportRecordedFit, AFreshSessionIsDrawnFromItsRecordWithoutRunningTheEstimator) {
  testing::ScratchDir dir("report_recorded_fit");
  WriteSession(dir.path());
  CloseWithEstimateOfRecord(dir.path(), true);
  ReportOptions options = Fast();
  options.output = dir.path() / "recorded.html";
  const auto drawn = WriteSessionReport(dir.path(), options);
  ASSERT_TRUE(drawn.has_value()) << drawn.error().ToString();
  EXPECT_FALSE(drawn->estimate_rerun);
  EXPECT_FALSE(AnyWarningWith(drawn->warnings, "re-run"));
  const json data = ReportData(Read(drawn->html));
  // The page's estimate is the record's.
  EXPECT_EQ(data["derived"]["estimate"], SessionJson(dir.path())["outcome"]["estimate"]);

  // --refit: the estimator runs again, finds the recorded numbers, and draws the same fit.
  options.refit = true;
  options.output = dir.path() / "refit.html";
  const auto refit = WriteSessionReport(dir.path(), options);
  ASSERT_TRUE(refit.has_value()) << refit.error().ToString();
  EXPECT_TRUE(refit->estimate_rerun);
  EXPECT_FALSE(AnyWarningWith(refit->warnings, "differs from the recorded one"));
  const json refit_data = ReportData(Read(refit->html));
  ASSERT_EQ(data["figures"].size(), refit_data["figures"].size());
  for (std::size_t i = 0; i < data["figures"].size(); ++i) {
    const std::string name = data["figures"][i].value("name", std::string());
    if (name.rfind("channels-run-", 0) == 0 || name.rfind("residuals-run-", 0) == 0) {
      EXPECT_EQ(data["figures"][i], refit_data["figures"][i]) << name;
    }
  }
}

TEST(ReportRecordedFit, ARecordFromBeforeTheFittedRunsWereKeptIsReRunWithAWarning) {
  testing::ScratchDir dir("report_old_record");
  WriteSession(dir.path());
  CloseWithEstimateOfRecord(dir.path(), false);
  const auto drawn = WriteSessionReport(dir.path(), Fast());
  ASSERT_TRUE(drawn.has_value()) << drawn.error().ToString();
  EXPECT_TRUE(drawn->estimate_rerun);
  EXPECT_TRUE(AnyWarningWith(drawn->warnings, "keeps no fitted runs"));
}

// Issue 26 §4: what the fit left, per run, from the recorded fit: a histogram of the residuals
// against the Gaussian of σ̂ and their spectrum against the white-noise level 2σ̂²/fs. The session
// is white noise of σ = 1e-4 at 100 Hz (WriteSession), so both must read as such.
TEST(ReportRecordedFit, EachRunShowsItsResidualHistogramAndSpectrum) {
  testing::ScratchDir dir("report_residual_figures");
  WriteSession(dir.path());
  CloseWithEstimateOfRecord(dir.path(), true);
  const auto drawn = WriteSessionReport(dir.path(), Fast());
  ASSERT_TRUE(drawn.has_value()) << drawn.error().ToString();
  EXPECT_FALSE(drawn->estimate_rerun);
  const std::string html = Read(drawn->html);
  const json data = ReportData(html);
  const json session = SessionJson(dir.path());
  const auto figure = [&](const std::string& name) {
    for (const json& f : data["figures"])
      if (f.value("name", std::string()) == name) return f;
    return json();
  };
  for (int run = 1; run <= 4; ++run) {
    const std::string id = std::to_string(run);
    for (const std::string kind : {"residual-histogram-run-", "residual-spectrum-run-"})
      EXPECT_NE(Section(html, run).find("data-figure=\"" + kind + id + "\""), std::string::npos)
          << kind << id;
    const json histogram = figure("residual-histogram-run-" + id);
    ASSERT_TRUE(histogram.is_object()) << id;
    ASSERT_EQ(histogram["series"].size(), 2u);
    // The step line's area is the share of residuals binned: all of them but a few beyond ±5σ̂.
    const auto x = histogram["series"][0]["x"].get<std::vector<double>>();
    const auto y = histogram["series"][0]["y"].get<std::vector<double>>();
    ASSERT_EQ(x.size(), y.size());
    double area = 0.0;
    for (std::size_t k = 1; k < x.size(); ++k) area += (x[k] - x[k - 1]) * y[k];
    EXPECT_NEAR(area, 1.0, 0.01) << id;
    EXPECT_EQ(histogram["series"][1]["model"], true);
    const json spectrum = figure("residual-spectrum-run-" + id);
    ASSERT_TRUE(spectrum.is_object()) << id;
    EXPECT_EQ(spectrum["y_log"], true);
    ASSERT_EQ(spectrum["series"].size(), 5u);  // four channels and the white-noise level
    EXPECT_EQ(spectrum["series"][4]["model"], true);
    // The level is 2σ̂²/fs of the run's σ̂ as its fit recorded it (σ = 1e-4 simulated).
    double sigma = std::nan("");
    for (const json& r : session["outcome"]["estimate"]["fit"]["runs"])
      if (r["run"] == run) sigma = r["noise_sigma"].get<double>();
    EXPECT_NEAR(sigma, 1e-4, 1e-5) << id;
    const double level = spectrum["series"][4]["y"].get<std::vector<double>>().at(0);
    EXPECT_NEAR(level / (2 * sigma * sigma / 100.0), 1.0, 1e-5) << id;
    // 200 samples per run: the channels' mean density is the white level, within its scatter.
    double mean = 0.0;
    std::size_t count = 0;
    for (int c = 0; c < 4; ++c)
      for (const double v : spectrum["series"][c]["y"].get<std::vector<double>>()) {
        mean += v;
        ++count;
      }
    EXPECT_NEAR(mean / static_cast<double>(count) / level, 1.0, 0.3) << id;
  }
}

}  // namespace
}  // namespace hrgbench::report
