// WriteSessionReport on bad input and on a machine without its helpers: a run file missing or
// empty, a run not complete, no run at all, session.json unreadable or of another format, Chart.js,
// gnuplot or Chromium missing; and gnuplot and Chromium when present. Sessions:
// report_test_session.hpp.
#include <regex>

#include "report_test_session.hpp"

namespace hrgbench::report {
namespace {

using namespace testing_support;
namespace fs = std::filesystem;
using nlohmann::json;

TEST(SessionReport, MissingRunFileIsReportedBesideItsRunAndTheRestRendered) {
  testing::ScratchDir dir("report_missing");
  WriteSession(dir.path());
  fs::remove(dir.path() / "runs" / "run-002.csv");
  const auto result = WriteSessionReport(dir.path(), Fast());
  ASSERT_TRUE(result) << result.error().ToString();
  const std::string html = Read(result->html);
  const std::string run2 = Section(html, 2);
  ASSERT_FALSE(run2.empty());
  EXPECT_NE(run2.find("<li class=\"warning\" data-run=\"2\">run 2: not estimated and not drawn, "
                      "its file is missing"),
            std::string::npos);
  EXPECT_NE(run2.find("run-002.csv"), std::string::npos);
  EXPECT_EQ(html.find("data-figure=\"channels-run-2\""), std::string::npos);
  for (int run : {1, 3, 4})
    EXPECT_NE(Section(html, run).find("data-figure=\"residuals-run-" + std::to_string(run) + "\""),
              std::string::npos);
  // Three runs still estimate: the estimate is there.
  EXPECT_TRUE(ReportData(html)["derived"]["estimate"]["delta"].is_array());
}

TEST(SessionReport, EmptyRunIsReportedBesideItsRun) {
  testing::ScratchDir dir("report_empty");
  WriteSession(dir.path());
  std::ofstream(dir.path() / "runs" / "run-003.csv") << "t_s,y1,y2,y3,y4\n";
  const auto result = WriteSessionReport(dir.path(), Fast());
  ASSERT_TRUE(result) << result.error().ToString();
  const std::string html = Read(result->html);
  const std::string run3 = Section(html, 3);
  EXPECT_NE(run3.find("<li class=\"warning\" data-run=\"3\">run 3: not estimated and not drawn, "
                      "cannot be read"),
            std::string::npos);
  EXPECT_NE(run3.find("run-003.csv"), std::string::npos);
  EXPECT_EQ(html.find("data-figure=\"forms-run-3\""), std::string::npos);
  EXPECT_NE(html.find("data-figure=\"forms-run-4\""), std::string::npos);
}

TEST(SessionReport, RunNotCompleteIsShownAsSuchAndLeftOut) {
  testing::ScratchDir dir("report_aborted");
  WriteSession(dir.path());
  json doc = SessionJson(dir.path());
  doc["runs"][3]["status"] = "aborted";
  std::ofstream(dir.path() / "session.json") << doc.dump();
  const auto result = WriteSessionReport(dir.path(), Fast());
  ASSERT_TRUE(result) << result.error().ToString();
  const std::string html = Read(result->html);
  const std::string run4 = Section(html, 4);
  EXPECT_NE(run4.find("Not drawn: status &#39;aborted&#39;"), std::string::npos) << run4;
  EXPECT_EQ(html.find("data-figure=\"channels-run-4\""), std::string::npos);
  // Whatever the reader said about run 4 is in run 4's section, not at the top.
  EXPECT_EQ(Top(html).find("run 4"), std::string::npos);
  EXPECT_NE(html.find("data-figure=\"channels-run-3\""), std::string::npos);
}

TEST(SessionReport, NoLoadableRunStillRendersTheRecord) {
  testing::ScratchDir dir("report_norun");
  WriteSession(dir.path(), RecordedOutcome());
  fs::remove_all(dir.path() / "runs");
  const auto result = WriteSessionReport(dir.path(), Fast());
  ASSERT_TRUE(result) << result.error().ToString();
  const std::string html = Read(result->html);
  EXPECT_NE(html.find("<div id=\"outcome\" data-kind=\"FAIL\">"), std::string::npos);
  EXPECT_NE(Top(html).find("no run could be loaded"), std::string::npos);
  EXPECT_EQ(html.find("<canvas data-figure=\"channels-run"), std::string::npos);
  // The recorded δ still gives the anisotropy.
  EXPECT_NE(html.find("data-figure=\"anisotropy\""), std::string::npos);
  EXPECT_GT(CheckNumbers(html, SessionJson(dir.path()), ReportData(html)), 20);
}

TEST(SessionReport, UnreadableSessionJsonIsRefusedNamingFileAndField) {
  testing::ScratchDir dir("report_badjson");
  WriteSession(dir.path());
  std::ofstream(dir.path() / "session.json")
      << "{\"format\": \"hrgbench-session\", \"version\": 1,";
  auto result = WriteSessionReport(dir.path(), Fast());
  ASSERT_FALSE(result);
  EXPECT_EQ(result.error().file.filename(), "session.json");
  EXPECT_FALSE(fs::exists(dir.path() / "report" / "report.html"));

  WriteSession(dir.path());
  json valid = SessionJson(dir.path());
  valid["format"] = "something-else";
  std::ofstream(dir.path() / "session.json") << valid.dump();
  result = WriteSessionReport(dir.path(), Fast());
  ASSERT_FALSE(result);
  EXPECT_EQ(result.error().field, "format");
  EXPECT_NE(result.error().ToString().find("session.json"), std::string::npos);
}

TEST(SessionReport, MissingChartJsIsAClearError) {
  testing::ScratchDir dir("report_nochart");
  WriteSession(dir.path());
  ReportOptions o = Fast();
  o.chart_js = dir.path() / "no-such-chart.min.js";
  const auto result = WriteSessionReport(dir.path(), o);
  ASSERT_FALSE(result);
  EXPECT_NE(result.error().message.find("libjs-chart.js"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir.path() / "report" / "report.html"));
}

TEST(SessionReport, MissingGnuplotAndChromiumAreWarningsNotFailures) {
  testing::ScratchDir dir("report_notools");
  WriteSession(dir.path());
  testing::ScratchDir empty("report_emptypath");
  const std::string saved = std::getenv("PATH") ? std::getenv("PATH") : "";
  ::setenv("PATH", empty.path().c_str(), 1);
  ReportOptions o;
  o.chromium = "chromium-not-installed-here";
  const auto result = WriteSessionReport(dir.path(), o);
  ::setenv("PATH", saved.c_str(), 1);
  ASSERT_TRUE(result) << result.error().ToString();
  EXPECT_TRUE(result->pdf.empty());
  EXPECT_TRUE(result->figures.empty());
  const std::string html = Read(result->html);
  EXPECT_NE(Top(html).find("<li class=\"warning\" data-run=\"0\">figures for documents (SVG) not "
                           "drawn: gnuplot could not be started"),
            std::string::npos);
  bool pdf_warning = false;
  for (const std::string& w : result->warnings)
    pdf_warning = pdf_warning || w.find("no PDF: chromium-not-installed-here") == 0;
  EXPECT_TRUE(pdf_warning);
}

TEST(SessionReport, GnuplotDrawsEveryFigureAsSvg) {
  HRGBENCH_REQUIRE(OnPath("gnuplot"), "gnuplot (Debian gnuplot-nox) not on PATH");
  testing::ScratchDir dir("report_svg");
  WriteSession(dir.path());
  ReportOptions o = Fast();
  o.figures = true;
  const auto result = WriteSessionReport(dir.path(), o);
  ASSERT_TRUE(result) << result.error().ToString();
  EXPECT_EQ(result->figures.size(), 30u);  // 7 per run, the anisotropy, std vs bound
  for (const fs::path& f : result->figures) {
    EXPECT_EQ(f.parent_path(), dir.path() / "report");
    EXPECT_NE(Read(f).find("<svg"), std::string::npos) << f;
  }
  EXPECT_TRUE(fs::exists(dir.path() / "report" / "channels-run-4.svg"));
}

TEST(SessionReport, ChromiumPrintsThePdf) {
  const char* override_binary = std::getenv("HRGBENCH_CHROMIUM");
  HRGBENCH_REQUIRE(override_binary != nullptr || OnPath("chromium"),
                   "chromium (Debian chromium) not on PATH");
  testing::ScratchDir dir("report_pdf");
  WriteSession(dir.path());
  ReportOptions o = Fast();
  o.pdf = true;
  const auto result = WriteSessionReport(dir.path(), o);
  ASSERT_TRUE(result) << result.error().ToString();
  ASSERT_EQ(result->pdf, dir.path() / "report" / "report.pdf");
  const std::string pdf = Read(result->pdf);
  EXPECT_EQ(pdf.substr(0, 5), "%PDF-");
  // The sheet: A4 by default (595 × 842 pt), US Letter on request (612 × 792 pt); the page's
  // @page rule sets it, so Chromium's own default (Letter) never decides.
  const auto sheet = [](const std::string& bytes) {
    const std::regex box(R"(/MediaBox\s*\[\s*0\s+0\s+([0-9.]+)\s+([0-9.]+)\s*\])");
    std::smatch m;
    if (!std::regex_search(bytes, m, box)) return std::pair<double, double>{0.0, 0.0};
    return std::pair<double, double>{std::stod(m[1]), std::stod(m[2])};
  };
  const auto [a4_w, a4_h] = sheet(pdf);
  EXPECT_NEAR(a4_w, 595.3, 2.0);
  EXPECT_NEAR(a4_h, 841.9, 2.0);
  o.paper = PaperSize::kLetter;
  const auto letter = WriteSessionReport(dir.path(), o);
  ASSERT_TRUE(letter) << letter.error().ToString();
  const auto [letter_w, letter_h] = sheet(Read(letter->pdf));
  EXPECT_NEAR(letter_w, 612.0, 2.0);
  EXPECT_NEAR(letter_h, 792.0, 2.0);
}

// The unit's fixture position heads the report (a unit's report must say where it sat).
TEST(SessionReport, AFixtureUnitsReportNamesItsPosition) {
  testing::ScratchDir dir("report_fixture");
  WriteSession(dir.path(), {{"fixture", {{"position", "B"}, {"folder", "fixture-1"}}}});
  const auto result = WriteSessionReport(dir.path(), Fast());
  ASSERT_TRUE(result) << result.error().ToString();
  EXPECT_NE(Read(result->html).find("<tr><th>fixture position</th><td>B</td></tr>"),
            std::string::npos);
}

// Issue 26 §1: who ran the session and who confirmed each operator prompt, when, head the report.
TEST(SessionReport, TheOperatorAndEveryPromptWithWhoAnsweredItAreInTheReport) {
  testing::ScratchDir dir("report_prompts");
  WriteSession(dir.path(),
               {{"operator", "OP-R"},
                {"prompts", nlohmann::json::array(
                                {{{"id", "mount"},
                                  {"at", "start"},
                                  {"text", "Mount <the> unit."},
                                  {"shown", {{"utc", "2026-11-27T04:00:00.000000Z"}}},
                                  {"answer", "confirmed"},
                                  {"by", "OP-R"},
                                  {"how", "panel"},
                                  {"answered", {{"utc", "2026-11-27T04:01:30.000000Z"}}}},
                                 {{"id", "remove"},
                                  {"at", "end"},
                                  {"text", "Take it off."},
                                  {"shown", {{"utc", "2026-11-27T04:20:00.000000Z"}}},
                                  {"answer", "interrupted"},
                                  {"reason", "aborted by operator while prompt 'remove' was open"},
                                  {"answered", {{"utc", "2026-11-27T04:20:05.000000Z"}}}}})}});
  const auto result = WriteSessionReport(dir.path(), Fast());
  ASSERT_TRUE(result) << result.error().ToString();
  const std::string html = Read(result->html);
  EXPECT_NE(html.find("<tr><th>operator</th><td>OP-R</td></tr>"), std::string::npos);
  EXPECT_NE(html.find("<tr><td>mount</td><td>start</td><td>Mount &lt;the&gt; unit.</td>"
                      "<td>confirmed</td><td>OP-R</td><td>panel</td>"
                      "<td>2026-11-27T04:00:00.000000Z</td><td>2026-11-27T04:01:30.000000Z</td>"
                      "</tr>"),
            std::string::npos);
  EXPECT_NE(html.find("<td>interrupted: aborted by operator while prompt &#39;remove&#39; was "
                      "open</td>"),
            std::string::npos)
      << html.substr(html.find("id=\"prompts\""), 1200);
}

}  // namespace
}  // namespace hrgbench::report
