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

}  // namespace
}  // namespace hrgbench::report
