// The tuning's section of the session report (report/tune_data.hpp, page_tune_section.cpp): a
// session folder with a tune.json as `hrg-bench tune` writes it (docs/bench/tuning.md), the page
// against it. The °/h conversions and the drawn curves are computed here from the document's
// numbers (1 rad/s = 180/π·3600 °/h; the fitted error b + Σ c_n·cos 2nθ + s_n·sin 2nθ), not by the
// code under test.
#include <cmath>
#include <numbers>
#include <regex>

#include "report_test_session.hpp"

namespace hrgbench::report {
namespace {

using namespace testing_support;
namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kDegH = 180.0 / std::numbers::pi * 3600.0;

json Hold(double omega, double bias, double c1, double s1, double c2, double s2) {
  return {{"omega_set_rad_s", omega},
          {"omega_rad_s", omega + 1e-5},
          {"omega_std_error_rad_s", 1e-7},
          {"omega_source", "angle"},
          {"duration_s", 20.0},
          {"samples", 20000},
          {"sequence_gaps", 0},
          {"bias_rad_s", bias},
          {"bias_std_rad_s", 1e-8},
          {"cos_rad_s", {c1, c2}},
          {"cos_std_rad_s", {1e-8, 1e-8}},
          {"sin_rad_s", {s1, s2}},
          {"sin_std_rad_s", {1e-8, 1e-8}},
          {"angle_dependent_rms_rad_s", std::sqrt((c1 * c1 + s1 * s1 + c2 * c2 + s2 * s2) / 2)},
          {"angle_span_rad", 12.6}};
}

json TuneDocument() {
  json doc;
  doc["format"] = "hrgbench-tune";
  doc["version"] = 1;
  doc["ok"] = true;
  doc["block_at_end"] = "refined";
  doc["restored"] = false;
  doc["holds"] = {
      {"before", {Hold(0.3, 1e-4, 4e-3, -2e-3, 1e-5, 0.0), Hold(-0.3, -1e-4, -4e-3, 2e-3, 0, 0)}},
      {"refine", {Hold(0.3, 2e-6, 1e-6, 0, 0, 0), Hold(-0.3, 2e-6, -1e-6, 0, 0, 0)}},
      {"after", {Hold(0.3, 1e-8, 2e-8, 1e-8, 0, 0), Hold(-0.3, -3e-8, -1e-8, 2e-8, 0, 0)}}};
  doc["verification"] = {{"rates",
                          {{{"omega_rad_s", 0.30001},
                            {"before_rms_rad_s", 3.2e-3},
                            {"after_rms_rad_s", 1.6e-8},
                            {"predicted_rms_rad_s", 2e-8},
                            {"chi2", 2.5},
                            {"met", true}},
                           {{"omega_rad_s", -0.29999},
                            {"before_rms_rad_s", 3.1e-3},
                            {"after_rms_rad_s", 1.5e-8},
                            {"predicted_rms_rad_s", 2e-8},
                            {"chi2", 3.5},
                            {"met", true}}}},
                         {"chi2", 6.0},
                         {"chi2_dof", 6},
                         {"chi2_limit", 22.46},
                         {"consistent", true}};
  doc["scale_factor"] = {{"bias_rad_s", -1e-8},
                         {"bias_std_rad_s", 5e-9},
                         {"error_ppm", 0.12},
                         {"error_std_ppm", 0.04},
                         {"nonlinearity_ppm", nullptr},
                         {"chi2", 0.0},
                         {"dof", 0}};
  doc["zero_rate"] = {{"hold", Hold(0.0, 0.0, 0, 0, 0, 0)},
                      {"bias_rad_s", 1e-8},
                      {"allan",
                       {{{"tau_s", 0.01},
                         {"deviation_rad_s", 1e-4},
                         {"lower_rad_s", 9e-5},
                         {"upper_rad_s", 1.1e-4},
                         {"edf", 100.0}},
                        {{"tau_s", 0.1},
                         {"deviation_rad_s", 1e-5},
                         {"lower_rad_s", 8e-6},
                         {"upper_rad_s", 1.3e-5},
                         {"edf", 10.0}}}},
                      {"arw_rad_per_sqrt_s", 1e-6},
                      {"arw_interval", {0.9e-6, 1.1e-6}},
                      {"bias_instability_rad_s", 2e-6},
                      {"bias_instability_interval", {1e-6, 4e-6}},
                      {"bias_instability_tau_s", 0.1},
                      {"bias_instability_reached", false}};
  doc["verdict"] = {{"outcome", "PASS"},
                    {"reason", ""},
                    {"checks",
                     {{{"name", "bias_deg_h"},
                       {"value", -0.002},
                       {"std", 0.001},
                       {"max", 1.0},
                       {"status", "PASS"},
                       {"zone", "accept"},
                       {"expanded_uncertainty", 0.002},
                       {"retest", false},
                       {"message", "bias_deg_h = -0.002 ± 0.001 °/h in [-1, 1] °/h"}}}}};
  return doc;
}

void WriteTune(const fs::path& dir, const std::string& text) {
  std::ofstream out(dir / "tune.json", std::ios::binary);
  out << text;
}

std::string TuningSection(const std::string& html) {
  const std::size_t at = html.find("<section id=\"tuning\">");
  if (at == std::string::npos) return {};
  return html.substr(at, html.find("</section>", at) - at);
}

const json* FigureNamed(const json& data, const std::string& name) {
  for (const json& f : data["figures"])
    if (f.value("name", "") == name) return &f;
  return nullptr;
}

TEST(ReportTuneSection, ATunedUnitsPageShowsTheTuningAsRecorded) {
  testing::ScratchDir dir("report_tune");
  WriteSession(dir.path(), RecordedOutcome());
  const json tune = TuneDocument();
  WriteTune(dir.path(), tune.dump(2));
  const auto result = WriteSessionReport(dir.path(), Fast());
  ASSERT_TRUE(result) << result.error().ToString();
  const std::string html = Read(result->html);
  const std::string section = TuningSection(html);
  ASSERT_FALSE(section.empty());
  EXPECT_NE(section.find("<div id=\"tune-outcome\" data-kind=\"PASS\">tune PASS</div>"),
            std::string::npos);
  EXPECT_NE(section.find("the block refined"), std::string::npos);
  // Every data-tune-source resolves in tune.json to its data-value, exactly.
  int checked = 0;
  const std::regex number("data-tune-source=\"([^\"]*)\" data-value=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(section.begin(), section.end(), number);
       it != std::sregex_iterator(); ++it, ++checked) {
    const json::json_pointer p((*it)[1].str());
    ASSERT_TRUE(tune.contains(p)) << (*it)[1];
    EXPECT_EQ(tune.at(p).get<double>(), Parse((*it)[2])) << (*it)[1];
  }
  EXPECT_GE(checked, 12);
  // The rest of the page's numbers still resolve (session.json, the data block).
  const json data = ReportData(html);
  EXPECT_GT(CheckNumbers(html, SessionJson(dir.path()), data), 40);
  // Per rate, in °/h: the recorded rad/s converted.
  const json& rates = data["derived"]["tune"]["rates"];
  ASSERT_EQ(rates.size(), 2u);
  EXPECT_NEAR(rates[0]["before_deg_h"].get<double>(), 3.2e-3 * kDegH, 1e-9 * kDegH);
  EXPECT_NEAR(rates[1]["after_deg_h"].get<double>(), 1.5e-8 * kDegH, 1e-12 * kDegH);
  EXPECT_NEAR(rates[0]["factor"].get<double>(), 3.2e-3 / 1.6e-8, 1e-3);
  // "With p from the free runs": the refine hold at the same rate's RMS.
  EXPECT_NEAR(rates[1]["with_p_deg_h"].get<double>(), 1e-6 / std::sqrt(2.0) * kDegH, 1e-6);
  EXPECT_NEAR(data["derived"]["tune"]["zero_rate"]["arw_deg_per_sqrt_h"].get<double>(),
              1e-6 * 180.0 / std::numbers::pi * 60.0, 1e-12);
  // The curves: the +0.3 rad/s before hold at θ = 0° and 45° (fitted bias and harmonics).
  const json* before = FigureNamed(data, "tune-rate-error-before");
  ASSERT_NE(before, nullptr);
  ASSERT_EQ((*before)["series"].size(), 2u);
  const json& y = (*before)["series"][0]["y"];
  EXPECT_NEAR(y[0].get<double>(), (1e-4 + 4e-3 + 1e-5) * kDegH, 1e-4 * kDegH * 1e-3);
  EXPECT_NEAR(y[45].get<double>(), (1e-4 - 2e-3 - 1e-5) * kDegH, 1e-4 * kDegH * 1e-3);
  const json* after = FigureNamed(data, "tune-rate-error-after");
  ASSERT_NE(after, nullptr);
  EXPECT_EQ((*after)["series"].size(), 4u);  // after and, dashed, with p from the free runs
  EXPECT_TRUE((*after)["series"][3]["model"].get<bool>());
  const json* allan = FigureNamed(data, "tune-allan");
  ASSERT_NE(allan, nullptr);
  EXPECT_TRUE((*allan)["x_log"].get<bool>());
  EXPECT_NEAR((*allan)["series"][0]["y"][1].get<double>(), 1e-5 * kDegH, 1e-3);
  ASSERT_NE(FigureNamed(data, "tune-scale-factor"), nullptr);
  for (const char* name :
       {"tune-rate-error-before", "tune-rate-error-after", "tune-scale-factor", "tune-allan"})
    EXPECT_NE(section.find(std::string("data-figure=\"") + name + "\""), std::string::npos) << name;
  // Bias instability not reached: the page says it is a bound.
  EXPECT_NE(section.find("bias instability below"), std::string::npos);
}

TEST(ReportTuneSection, AnUntunedUnitsPageHasNoSectionAndNoWarning) {
  testing::ScratchDir dir("report_untuned");
  WriteSession(dir.path(), RecordedOutcome());
  const auto result = WriteSessionReport(dir.path(), Fast());
  ASSERT_TRUE(result) << result.error().ToString();
  const std::string html = Read(result->html);
  EXPECT_TRUE(TuningSection(html).empty());
  EXPECT_EQ(html.find("tune.json"), std::string::npos);
  EXPECT_TRUE(ReportData(html)["derived"]["tune"].is_null());
}

// A tune.json the report cannot read: the page is made without the section, and a warning names
// the file and what is wrong with it.
TEST(ReportTuneSection, AnUnreadableTuningRecordIsAWarningNamingItNeverAFailure) {
  json wrong_format = TuneDocument();
  wrong_format["format"] = "something-else";
  json no_verdict = TuneDocument();
  no_verdict.erase("verdict");
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  const struct {
    std::string text;
    std::string says;
  } cases[] = {{wrong_format.dump(), "format"},
               {no_verdict.dump(), "verdict"},
               {"{\"format\": \"hrgbench-tune\", ", "not a JSON object"},
               {deep, "nested deeper than 16 levels"}};
  for (const auto& c : cases) {
    testing::ScratchDir dir("report_tune_bad");
    WriteSession(dir.path(), RecordedOutcome());
    WriteTune(dir.path(), c.text);
    const auto result = WriteSessionReport(dir.path(), Fast());
    ASSERT_TRUE(result) << result.error().ToString();
    const std::string html = Read(result->html);
    EXPECT_TRUE(TuningSection(html).empty()) << c.says;
    bool warned = false;
    for (const std::string& w : result->warnings)
      warned = warned ||
               (w.find("tune.json") != std::string::npos && w.find(c.says) != std::string::npos);
    EXPECT_TRUE(warned) << c.says;
    EXPECT_NE(html.find("tuning not shown"), std::string::npos) << c.says;
  }
}

}  // namespace
}  // namespace hrgbench::report
