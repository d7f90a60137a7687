// WriteSessionReport on sessions built here: simulated runs (SimulateRuns: closed-form model,
// seeded noise, δ and ξ below, four runs at Ω = 0.1, −0.3, 1, −1 rad/s, 2 s at 100 Hz) written with
// the session library's own writers, then damaged or extended as each test says. The page is
// checked against its contract (session_report.hpp) by reading the HTML text back.
#include "hrgbench/report/session_report.hpp"

#include <unistd.h>

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hrgbench/estimator/simulation.hpp"
#include "hrgbench/session/session.hpp"
#include "record_test_dir.hpp"
#include "required_tool.hpp"

namespace hrgbench::report {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kOmegas[] = {0.1, -0.3, 1.0, -1.0};

void WriteSession(const fs::path& dir, const json& extra = json::object()) {
  std::vector<estimator::RunPlan> plans;
  for (int k = 0; k < 4; ++k) {
    estimator::RunPlan p;
    p.omega_rad_s = kOmegas[k];
    p.b = 0.1;
    p.theta_rad = k * M_PI / 12.0;
    p.sample_rate_hz = 100.0;
    p.duration_s = 2.0;
    plans.push_back(p);
  }
  estimator::SimulationOptions truth;
  truth.delta << -1e-3, 0.3, 2e-6, -1e-6, 3e-5, -2e-5;
  truth.xi << 0.01, -0.003, 0.002, 0.004;
  truth.sigma = 1e-4;
  truth.seed = 7;
  const std::vector<estimator::RunData> runs = estimator::SimulateRuns(plans, truth);
  ASSERT_EQ(runs.size(), 4u);
  session::Session s;
  s.serial = "TEST-0001";
  s.sample_rate_hz = 100.0;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    session::RunEntry entry;
    entry.id = static_cast<int>(k + 1);
    entry.file = "runs/run-00" + std::to_string(k + 1) + ".csv";
    entry.omega_rad_s = kOmegas[k];
    s.runs.push_back(entry);
    session::RunSamples samples;
    samples.t_s = runs[k].t_s;
    samples.y = runs[k].y;
    ASSERT_TRUE(session::WriteRunCsv(dir / entry.file, samples));
  }
  s.document = json{{"station", {{"name", "test station"}}},
                    {"simulation",
                     {{"delta", std::vector<double>(truth.delta.begin(), truth.delta.end())},
                      {"xi", std::vector<double>(truth.xi.begin(), truth.xi.end())}}}};
  s.document.update(extra);
  ASSERT_TRUE(session::WriteSessionJson(dir, s));
}

ReportOptions Fast() {
  ReportOptions o;
  o.pdf = false;
  o.figures = false;
  return o;
}

std::string Read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

json SessionJson(const fs::path& dir) { return json::parse(Read(dir / "session.json")); }

json ReportData(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"report-data\">";
  const std::size_t at = html.find(open);
  EXPECT_NE(at, std::string::npos);
  EXPECT_EQ(html.find(open, at + 1), std::string::npos) << "one data block";
  const std::size_t begin = at + open.size();
  return json::parse(html.substr(begin, html.find("</script>", begin) - begin));
}

// The text of run N's section ("" when there is none).
std::string Section(const std::string& html, int run) {
  const std::string open = "<section class=\"run\" id=\"run-" + std::to_string(run) + "\"";
  const std::size_t at = html.find(open);
  if (at == std::string::npos) return {};
  return html.substr(at, html.find("</section>", at) - at);
}

std::string Top(const std::string& html) {
  return html.substr(0, html.find("<section class=\"run\""));
}

double Parse(const std::string& text) {
  double v = std::nan("");
  std::from_chars(text.data(), text.data() + text.size(), v);
  return v;
}

// Every data-source resolves in session.json to the number in data-value (exactly: shortest
// round-trip text), every data-derived in the data block. Returns how many were checked.
int CheckNumbers(const std::string& html, const json& session, const json& data) {
  int checked = 0;
  const std::regex number("data-(source|derived)=\"([^\"]*)\" data-value=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(html.begin(), html.end(), number);
       it != std::sregex_iterator(); ++it) {
    const json& doc = (*it)[1] == "source" ? session : data;
    const std::string pointer = (*it)[2];
    const json::json_pointer p(pointer);
    EXPECT_TRUE(doc.contains(p)) << pointer;
    if (!doc.contains(p)) continue;
    EXPECT_TRUE(doc.at(p).is_number()) << pointer;
    EXPECT_EQ(doc.at(p).get<double>(), Parse((*it)[3])) << pointer;
    ++checked;
  }
  return checked;
}

bool OnPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  std::string d;
  while (std::getline(dirs, d, ':'))
    if (!d.empty() && ::access((fs::path(d) / program).c_str(), X_OK) == 0) return true;
  return false;
}

TEST(SessionReport, SimulatedSessionWithoutOutcomeFollowsTheContract) {
  testing::ScratchDir dir("report_sim");
  WriteSession(dir.path());
  const auto result = WriteSessionReport(dir.path(), Fast());
  ASSERT_TRUE(result) << result.error().ToString();
  EXPECT_EQ(result->html, dir.path() / "report" / "report.html");
  const std::string html = Read(result->html);
  EXPECT_EQ(html.size(), result->html_bytes);
  // Offline: no URL anywhere, Chart.js inlined.
  EXPECT_EQ(html.find("http://"), std::string::npos);
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  EXPECT_NE(html.find("Chart.js v"), std::string::npos);
  EXPECT_NE(html.find("reportReady = \"true\""), std::string::npos);
  EXPECT_NE(html.find("<div id=\"outcome\" data-kind=\"NOT RECORDED\">"), std::string::npos);
  // Every chart: a canvas in a figure with a caption, with the contract's names.
  std::set<std::string> names;
  const std::regex figure("<figure><canvas data-figure=\"([^\"]+)\"[^>]*></canvas><figcaption>");
  for (auto it = std::sregex_iterator(html.begin(), html.end(), figure);
       it != std::sregex_iterator(); ++it)
    names.insert((*it)[1]);
  std::size_t canvases = 0;
  for (std::size_t at = html.find("<canvas"); at != std::string::npos; at = html.find("<canvas", at + 1))
    ++canvases;
  EXPECT_EQ(canvases, names.size());
  std::set<std::string> expected = {"anisotropy", "std-vs-bound"};
  for (int run = 1; run <= 4; ++run)
    for (const char* kind : {"channels", "residuals", "orbit", "forms"})
      expected.insert(std::string(kind) + "-run-" + std::to_string(run));
  EXPECT_EQ(names, expected);
  // Every figure has its data, and each canvas is in its run's section.
  const json data = ReportData(html);
  std::set<std::string> specs;
  for (const json& f : data["figures"]) specs.insert(f["name"].get<std::string>());
  EXPECT_EQ(specs, expected);
  EXPECT_NE(Section(html, 3).find("data-figure=\"orbit-run-3\""), std::string::npos);
  // Numbers: the truth from session.json, the re-run estimate and the bound derived.
  EXPECT_GT(CheckNumbers(html, SessionJson(dir.path()), data), 40);
  EXPECT_NE(html.find("data-source=\"/simulation/delta/1\" data-value=\"0.3\""), std::string::npos);
  EXPECT_NE(html.find("data-derived=\"/derived/estimate/delta/1\""), std::string::npos);
  EXPECT_NE(html.find("data-derived=\"/derived/crlb/delta_std/1\""), std::string::npos);
  // The re-run estimate is right (within 5 std of the truth) and its std near the bound.
  const double d2 = data["derived"]["estimate"]["delta"][1];
  const double s2 = data["derived"]["estimate"]["delta_std"][1];
  const double b2 = data["derived"]["crlb"]["delta_std"][1];
  EXPECT_NEAR(d2, 0.3, 5 * s2);
  EXPECT_NEAR(s2 / b2, 1.0, 0.2);
  // The session-level warning about the missing outcome is at the top.
  EXPECT_NE(Top(html).find("<li class=\"warning\" data-run=\"0\">session.json has no outcome"),
            std::string::npos);
}

json RecordedOutcome() {
  return json::parse(R"({"outcome": {
    "kind": "FAIL", "exit_code": 1, "reason": "out of limits: tau_s",
    "failed_parameters": [{"name": "tau_s", "value": 1000.0, "min": 2000.0, "max": null}],
    "estimate": {"method": "ml",
      "delta": [-0.00101, 0.3001, 2e-6, -1e-6, 3e-5, -2e-5], "delta_std": [1e-6, 1e-4, 1e-6, 1e-6, 1e-6, 1e-6],
      "xi": [0.01, -0.003, 0.002, 0.004], "xi_std": [1e-4, 1e-4, 1e-4, 1e-4],
      "residual_rms": 1e-4, "noise_sigma": 1e-4, "samples_used": 800, "iterations": 4,
      "warnings": ["run 2: something odd in run two", "a session-level remark"],
      "engineering": {"frequency_hz": 5000.0, "frequency_source": "runs[].start",
        "quantities": [
          {"name": "tau_s", "label": "mean decay time τ", "unit": "s", "value": 1000.0, "std": 2.5,
           "determined": true, "note": ""},
          {"name": "q", "label": "quality factor Q", "unit": "", "value": null, "std": null,
           "determined": false, "note": "needs the carrier frequency"}]}},
    "verdict": {"overall": "FAIL", "fit_acceptable": true,
      "fit_checks": [{"run": 1, "name": "residual_ratio", "status": "PASS", "value": 1.01,
                      "max": 1.05, "message": "within"}],
      "limits": [{"quantity": "tau_s", "status": "FAIL", "value": 1000.0, "std": 2.5,
                  "min": 2000.0, "max": null, "message": "below its minimum"}]}}})");
}

TEST(SessionReport, RecordedOutcomeVerdictAndEngineeringAreShown) {
  testing::ScratchDir dir("report_outcome");
  WriteSession(dir.path(), RecordedOutcome());
  const auto result = WriteSessionReport(dir.path(), Fast());
  ASSERT_TRUE(result) << result.error().ToString();
  const std::string html = Read(result->html);
  EXPECT_NE(html.find("<div id=\"outcome\" data-kind=\"FAIL\">FAIL"), std::string::npos);
  EXPECT_NE(html.find("out of limits: tau_s"), std::string::npos);
  // Recorded numbers come from session.json, each resolvable.
  EXPECT_GT(CheckNumbers(html, SessionJson(dir.path()), ReportData(html)), 40);
  EXPECT_NE(html.find("data-source=\"/outcome/estimate/delta/1\" data-value=\"0.3001\""),
            std::string::npos);
  EXPECT_NE(html.find("data-source=\"/outcome/estimate/delta_std/1\" data-value=\"1e-04\""),
            std::string::npos);
  // Engineering: generic over the list; undetermined says so.
  EXPECT_NE(html.find("mean decay time τ"), std::string::npos);
  EXPECT_NE(html.find("data-source=\"/outcome/estimate/engineering/quantities/0/value\" "
                      "data-value=\"1000\""),
            std::string::npos);
  const std::size_t q = html.find("quality factor Q");
  ASSERT_NE(q, std::string::npos);
  EXPECT_NE(html.substr(q, 200).find("undetermined"), std::string::npos);
  // Limits and fit checks.
  EXPECT_NE(html.find("data-source=\"/outcome/verdict/limits/0/min\" data-value=\"2000\""),
            std::string::npos);
  EXPECT_NE(html.find("data-source=\"/outcome/verdict/fit_checks/0/value\" data-value=\"1.01\""),
            std::string::npos);
  // Warnings beside their run; the rest at the top.
  EXPECT_NE(Section(html, 2).find(
                "<li class=\"warning\" data-run=\"2\">run 2: something odd in run two</li>"),
            std::string::npos);
  EXPECT_NE(Top(html).find("<li class=\"warning\" data-run=\"0\">a session-level remark</li>"),
            std::string::npos);
  // The recorded δ1 is 10 std from the data's: the page says the model drawn is the re-run's.
  EXPECT_NE(Top(html).find("differs from the recorded one"), std::string::npos);
  // The anisotropy is from the recorded δ.
  EXPECT_EQ(ReportData(html)["derived"]["anisotropy"]["delta_source"], "/outcome/estimate/delta");
}

TEST(SessionReport, OutcomeWithoutEngineeringOrVerdictSaysNotRecorded) {
  testing::ScratchDir dir("report_older");
  json outcome = RecordedOutcome();
  outcome["outcome"]["estimate"].erase("engineering");
  outcome["outcome"].erase("verdict");
  WriteSession(dir.path(), outcome);
  const auto result = WriteSessionReport(dir.path(), Fast());
  ASSERT_TRUE(result) << result.error().ToString();
  const std::string html = Read(result->html);
  EXPECT_NE(html.find("Engineering quantities: <span class=\"na\">not recorded</span>"),
            std::string::npos);
  EXPECT_NE(html.find("Verdict: <span class=\"na\">not recorded</span>"), std::string::npos);
  EXPECT_NE(html.find("data-figure=\"channels-run-4\""), std::string::npos);
}

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
  std::ofstream(dir.path() / "session.json") << "{\"format\": \"hrgbench-session\", \"version\": 1,";
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
  EXPECT_EQ(result->figures.size(), 18u);  // 4 per run, the anisotropy, std vs bound
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
  EXPECT_EQ(Read(result->pdf).substr(0, 5), "%PDF-");
}

}  // namespace
}  // namespace hrgbench::report
