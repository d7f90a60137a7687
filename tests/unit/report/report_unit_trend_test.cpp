// Issue 26 §4: the unit's parameter trend across its sessions — not only a table: per key
// quantity a plot of value ± k·u per session (this one last), the limits drawn.

#include <gtest/gtest.h>

#include "report_test_session.hpp"

namespace hrgbench::report {
namespace {

using namespace testing_support;

std::size_t Count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(ReportUnitTrend, EachKeyQuantityIsPlottedAcrossSessionsWithItsLimits) {
  json record = RecordedOutcome();  // τ = 1000 ± 2.5 s against min 2000 s
  record["outcome"]["verdict"]["decision"] = {{"rule", "guarded_acceptance_retest"},
                                              {"coverage_factor", 2.0}};
  record["outcome"]["estimate"]["engineering"]["quantities"].push_back({{"name", "q_factor"},
                                                                        {"label", "Q"},
                                                                        {"unit", ""},
                                                                        {"value", 1.5e7},
                                                                        {"std", 1e3},
                                                                        {"determined", true},
                                                                        {"note", ""}});
  record["outcome"]["verdict"]["limits"].push_back({{"quantity", "q_factor"},
                                                    {"status", "PASS"},
                                                    {"value", 1.5e7},
                                                    {"std", 1e3},
                                                    {"min", 1e6},
                                                    {"max", 1e9},
                                                    {"message", ""}});
  testing::ScratchDir dir("report_unit_trend");
  WriteSession(dir.path(), record);
  ReportOptions options = Fast();
  UnitHistory history;
  history.store = "sqlite:///line/results.sqlite";
  const double tau[] = {1800.0, 1500.0, 1200.0};
  for (int i = 0; i < 3; ++i) {
    UnitHistoryEntry e;
    e.started_utc = "2026-11-2" + std::to_string(i) + "T10:00:00Z";
    e.station = "line-1";
    e.outcome = "PASS";
    e.values["tau_s"] = tau[i];
    if (i > 0) e.stds["tau_s"] = 3.0;  // the oldest stored no std: no bar
    e.values["q_factor"] = 1.5e7 + i * 1e4;
    history.sessions.push_back(e);
  }
  options.unit_history = history;
  const auto result = WriteSessionReport(dir.path(), options);
  ASSERT_TRUE(result.has_value()) << result.error().ToString();
  const std::string html = Read(result->html);
  const json data = ReportData(html);
  EXPECT_EQ(data["derived"]["unit_history"]["sessions"][1]["stds"]["tau_s"], 3.0);

  const std::size_t at =
      html.find("<svg class=\"trend\" data-quantity=\"tau_s\" data-points=\"4\"");
  ASSERT_NE(at, std::string::npos);
  EXPECT_LT(html.find("<section id=\"unit-history\">"), at);
  const std::string tau_plot = html.substr(at, html.find("</svg>", at) - at);
  EXPECT_EQ(Count(tau_plot, "<circle class=\"session\""), 4u);
  EXPECT_EQ(Count(tau_plot, "<line class=\"uncertainty\""), 3u);  // not the oldest
  EXPECT_EQ(Count(tau_plot, "<line class=\"limit\""), 1u);        // min 2000 s, near the values
  EXPECT_NE(tau_plot.find("bars ± 2·u; limits [2000, —]"), std::string::npos) << tau_plot;
  EXPECT_NE(tau_plot.find("<title>this session: 1000 ± 5</title>"), std::string::npos);
  // Q's limits are decades off its values: named at the edge, not drawn as lines that would
  // flatten every point.
  const std::size_t q = html.find("<svg class=\"trend\" data-quantity=\"q_factor\"");
  ASSERT_NE(q, std::string::npos);
  const std::string q_plot = html.substr(q, html.find("</svg>", q) - q);
  EXPECT_EQ(Count(q_plot, "<line class=\"limit\""), 0u);
  EXPECT_EQ(Count(q_plot, "class=\"limit-off-scale\""), 2u);
  // A quantity no session determined has no plot.
  EXPECT_EQ(html.find("data-quantity=\"angular_gain\""), std::string::npos);
}

}  // namespace
}  // namespace hrgbench::report
