// WriteSessionReport: the page against its contract (session_report.hpp), and what a bench session
// records (outcome, verdict, engineering quantities) shown as recorded. Sessions:
// report_test_session.hpp.
#include "report_test_session.hpp"

namespace hrgbench::report {
namespace {

using namespace testing_support;
namespace fs = std::filesystem;
using nlohmann::json;

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
  for (std::size_t at = html.find("<canvas"); at != std::string::npos;
       at = html.find("<canvas", at + 1))
    ++canvases;
  EXPECT_EQ(canvases, names.size());
  std::set<std::string> expected = {"anisotropy", "std-vs-bound"};
  for (int run = 1; run <= 4; ++run)
    for (const char* kind : {"channels", "motion", "residuals", "residual-histogram",
                             "residual-spectrum", "orbit", "forms"})
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
  // One name per parameter: δ2 and ξ4 read as the terminal's summary names them (it once said
  // "scale factor" where the report said "angular gain").
  EXPECT_NE(html.find("<td>δ2</td><td>angular gain (Bryan factor) [-]</td>"), std::string::npos);
  EXPECT_NE(html.find("<td>ξ4</td><td>pick-off angle error [-]</td>"), std::string::npos);
  EXPECT_EQ(html.find("scale factor"), std::string::npos);
  EXPECT_EQ(html.find("electrode misplacement"), std::string::npos);
}

// The Cramér–Rao bound is for white noise: a sandwich std (coloured residuals) above it measures
// the noise's colour, and the page must not call the ratio an inefficiency. With white noise it
// may.
TEST(SessionReport, TheBoundIsAnEfficiencyOnlyForAWhiteNoiseStd) {
  for (const std::string kind : {"white", "sandwich"}) {
    testing::ScratchDir dir("report_crlb_" + kind);
    json outcome = RecordedOutcome();
    outcome["outcome"]["estimate"]["fit"] = {{"covariance", kind}};
    WriteSession(dir.path(), outcome);
    const auto result = WriteSessionReport(dir.path(), Fast());
    ASSERT_TRUE(result) << result.error().ToString();
    const std::string html = Read(result->html);
    const json crlb = ReportData(html)["derived"]["crlb"];
    ASSERT_TRUE(crlb.is_object()) << kind;
    EXPECT_EQ(crlb["covariance"], kind);
    EXPECT_EQ(crlb["comparison"], kind == "white" ? "efficiency" : "noise colour");
    const bool claims_efficiency = html.find("1 is an efficient estimate") != std::string::npos;
    EXPECT_EQ(claims_efficiency, kind == "white") << kind;
  }
}

// Issue 26: value ± k·u drawn against each limit with its guard bands (report/guard_band_bar.hpp).
TEST(SessionReport, EachLimitIsDrawnWithItsIntervalAndGuardBands) {
  json record = RecordedOutcome();
  json& verdict = record["outcome"]["verdict"];
  verdict["decision"] = {{"rule", "guarded_acceptance_retest"}, {"coverage_factor", 2.0}};
  verdict["retest"] = true;
  verdict["limits"] = json::parse(R"([
    {"quantity": "xi1", "status": "FAIL", "value": 0.0244, "std": 0.0095, "min": -0.02,
     "max": 0.02, "message": "not accepted", "rule": "guarded_acceptance_retest",
     "zone": "undecided", "coverage_factor": 2.0, "expanded_uncertainty": 0.019,
     "interval_min": 0.0054, "interval_max": 0.0434, "acceptance_min": -0.001,
     "acceptance_max": 0.001, "retest": true},
    {"quantity": "delta2", "status": "PASS", "value": 0.3, "std": 1e-4, "min": 0.28,
     "max": 0.32, "message": "in", "rule": "guarded_acceptance_retest", "zone": "conforming",
     "coverage_factor": 2.0, "expanded_uncertainty": 2e-4, "interval_min": 0.2998,
     "interval_max": 0.3002, "acceptance_min": 0.2802, "acceptance_max": 0.3198, "retest": false},
    {"quantity": "tau_s", "status": "FAIL", "value": 1000.0, "std": 2.5, "min": 2000.0,
     "max": null, "message": "below its minimum"}])");
  testing::ScratchDir dir("report_guard_band");
  WriteSession(dir.path(), record);
  const auto result = WriteSessionReport(dir.path(), Fast());
  ASSERT_TRUE(result) << result.error().ToString();
  const std::string html = Read(result->html);
  const std::size_t xi1 =
      html.find("<svg class=\"guard-band\" data-quantity=\"xi1\" data-zone=\"undecided\"");
  ASSERT_NE(xi1, std::string::npos);
  const std::string bar = html.substr(xi1, html.find("</svg>", xi1) - xi1);
  EXPECT_NE(bar.find("<title>xi1 = 0.0244 ± 0.019 (k = 2) against [-0.02, 0.02], accepted "
                     "within [-0.001, 0.001]: undecided</title>"),
            std::string::npos)
      << bar;
  EXPECT_NE(bar.find("class=\"interval\""), std::string::npos);
  std::size_t guards = 0;
  for (std::size_t at = bar.find("class=\"guard\""); at != std::string::npos;
       at = bar.find("class=\"guard\"", at + 1))
    ++guards;
  EXPECT_EQ(guards, 2u);  // both sides of xi1's tolerance are guarded
  EXPECT_NE(html.find("data-quantity=\"delta2\" data-zone=\"conforming\""), std::string::npos);
  // A limit without a max (a hand-made row) has no bar; the table still reads.
  EXPECT_EQ(html.find("data-quantity=\"tau_s\""), std::string::npos);
  EXPECT_NE(html.find("Decision rule guarded_acceptance_retest, k = 2"), std::string::npos);
  EXPECT_NE(html.find("undecided within the guard band: retest"), std::string::npos);
}

// Issue 26: the limits table once wrote each value to six digits beside its std ("0.0244137 ±
// 0.0095"); a value carries the digits its std supports (GUM 7.2.6: the std to two significant
// digits, the value to the same place), data-value keeping every digit.
TEST(SessionReport, TheLimitsTableWritesEachValueToItsStdsPrecision) {
  json record = RecordedOutcome();
  record["outcome"]["verdict"]["limits"] = json::parse(R"([
    {"quantity": "xi1", "status": "FAIL", "value": 0.02441372, "std": 0.009512, "min": -0.02,
     "max": 0.02, "message": "above its maximum"},
    {"quantity": "tau_s", "status": "FAIL", "value": 1000.123456, "std": 2.5, "min": 2000.0,
     "max": null, "message": "below its minimum"}])");
  testing::ScratchDir dir("report_limits_precision");
  WriteSession(dir.path(), record);
  const auto result = WriteSessionReport(dir.path(), Fast());
  ASSERT_TRUE(result) << result.error().ToString();
  const std::string html = Read(result->html);
  const auto cell = [&](const std::string& pointer) {
    const std::string open = "data-source=\"" + pointer + "\" data-value=\"";
    const std::size_t at = html.find(open);
    if (at == std::string::npos) return std::string("(absent)");
    const std::size_t text = html.find('>', at) + 1;
    return html.substr(text, html.find('<', text) - text);
  };
  EXPECT_EQ(cell("/outcome/verdict/limits/0/value"), "0.0244");
  EXPECT_EQ(cell("/outcome/verdict/limits/0/std"), "0.0095");
  EXPECT_EQ(cell("/outcome/verdict/limits/1/value"), "1000.1");
  EXPECT_EQ(cell("/outcome/verdict/limits/1/std"), "2.5");
  EXPECT_NE(html.find("data-source=\"/outcome/verdict/limits/0/value\" data-value=\"0.02441372\""),
            std::string::npos);
  // The limits themselves are declared numbers, shown as declared.
  EXPECT_EQ(cell("/outcome/verdict/limits/1/min"), "2000");
}

// Issue 26: the anisotropy's legend was cut off — each axis' label carried its numbers
// ("high-frequency axis: Δf = … ± … mHz at θω = … ± …° on the shell"), wider than the square
// chart once padded square. The legend names the axes; the numbers are in the caption.
TEST(SessionReport, TheAnisotropyLegendNamesTheAxesAndTheCaptionHoldsTheirNumbers) {
  json record = RecordedOutcome();
  json& quantities = record["outcome"]["estimate"]["engineering"]["quantities"];
  const auto quantity = [](const char* name, const char* unit, double value, double std_dev) {
    return json{{"name", name},   {"label", name},      {"unit", unit}, {"value", value},
                {"std", std_dev}, {"determined", true}, {"note", ""}};
  };
  quantities.push_back(quantity("frequency_split_mhz", "mHz", 12.3456, 0.7123));
  quantities.push_back(quantity("frequency_axis_deg", "deg", -23.456, 1.234));
  quantities.push_back(quantity("damping_split_per_s", "1/s", 2.5e-5, 3e-6));
  quantities.push_back(quantity("damping_axis_deg", "deg", 31.2, 4.4));
  testing::ScratchDir dir("report_anisotropy_legend");
  WriteSession(dir.path(), record);
  const auto result = WriteSessionReport(dir.path(), Fast());
  ASSERT_TRUE(result) << result.error().ToString();
  const json data = ReportData(Read(result->html));
  json anisotropy;
  for (const json& f : data["figures"])
    if (f["name"] == "anisotropy") anisotropy = f;
  ASSERT_TRUE(anisotropy.is_object());
  std::vector<std::string> labels;
  for (const json& s : anisotropy["series"]) labels.push_back(s["label"].get<std::string>());
  EXPECT_EQ(labels,
            (std::vector<std::string>{"high-frequency axis", "low-frequency axis (+45°)",
                                      "fast-decay axis", "slow-decay axis (+45°)", "shell"}));
  const std::string caption = anisotropy["caption"].get<std::string>();
  EXPECT_NE(caption.find("high-frequency axis at θω = -23.5 ± 1.2° on the shell, Δf = 12.35 ± "
                         "0.71 mHz"),
            std::string::npos)
      << caption;
  EXPECT_NE(caption.find("fast-decay axis at θτ = 31.2 ± 4.4° on the shell"), std::string::npos)
      << caption;
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

}  // namespace
}  // namespace hrgbench::report
