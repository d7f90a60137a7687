// Issue 26 §4: temperature and frequency over each run, not only at its start and end. A run whose
// CSV has the electronics' temp_c and freq_hz columns is drawn from them; a run without says so
// and draws the recorded start and end only.

#include <gtest/gtest.h>

#include "report_test_session.hpp"

namespace hrgbench::report {
namespace {

using namespace testing_support;

// Run 1 gets temp_c and freq_hz columns (a ramp from 25 °C to 25.5 °C with one sample at 27 °C,
// and a frequency falling 0.02 Hz with one sample 0.5 Hz low: spikes the page must not lose to
// decimation); runs 1 and 2 get an end with temperature and frequency at start and end; runs 3
// and 4 have neither.
void WriteSessionWithConditions(const fs::path& dir) {
  WriteSession(dir);
  auto run = session::ReadRunCsv(dir / "runs/run-001.csv");
  ASSERT_TRUE(run.has_value()) << run.error().ToString();
  std::vector<double> temp_c(run->t_s.size());
  for (std::size_t k = 0; k < temp_c.size(); ++k) temp_c[k] = 25.0 + 0.25 * run->t_s[k];
  temp_c[77] = 27.0;
  run->extra_columns["temp_c"] = temp_c;
  std::vector<double> freq_hz(run->t_s.size());
  for (std::size_t k = 0; k < freq_hz.size(); ++k) freq_hz[k] = 5000.0 - 0.01 * run->t_s[k];
  freq_hz[123] = 4999.5;
  run->extra_columns["freq_hz"] = freq_hz;
  ASSERT_TRUE(session::WriteRunCsv(dir / "runs/run-001.csv", *run).has_value());
  json document = SessionJson(dir);
  for (int r = 0; r < 2; ++r)
    document["runs"][r]["end"] = {{"status", "complete"},
                                  {"temperature_start_c", 25.0},
                                  {"temperature_end_c", 25.5},
                                  {"frequency_start_hz", 5000.0},
                                  {"frequency_end_hz", 5000.01}};
  std::ofstream(dir / "session.json") << document.dump(2);
}

json FigureNamed(const json& data, const std::string& name) {
  for (const json& f : data["figures"])
    if (f.value("name", std::string()) == name) return f;
  return json();
}

double MaxOf(const json& values) {
  const std::vector<double> v = values.get<std::vector<double>>();
  return v.empty() ? std::nan("") : *std::max_element(v.begin(), v.end());
}

double MinOf(const json& values) {
  const std::vector<double> v = values.get<std::vector<double>>();
  return v.empty() ? std::nan("") : *std::min_element(v.begin(), v.end());
}

TEST(ReportRunConditions, TemperatureAndFrequencyOverTheRunFromTheirColumnsElseSaidNotRecorded) {
  testing::ScratchDir dir("report_run_conditions");
  WriteSessionWithConditions(dir.path());
  ReportOptions options = Fast();
  options.max_points_per_series = 40;  // decimated: the spike must survive as its bucket's max
  const auto result = WriteSessionReport(dir.path(), options);
  ASSERT_TRUE(result.has_value()) << result.error().ToString();
  const std::string html = Read(result->html);
  const json data = ReportData(html);
  EXPECT_GT(CheckNumbers(html, SessionJson(dir.path()), data), 40);

  const json& q1 = data["derived"]["runs"]["1"];
  EXPECT_EQ(q1["temperature_over_run"], "temp_c");
  EXPECT_EQ(q1["temperature_min_c"], 25.0);
  EXPECT_EQ(q1["temperature_max_c"], 27.0);
  EXPECT_EQ(q1["temperature_samples"], 200);
  EXPECT_NE(Section(html, 1).find("temperature over the run [°C]"), std::string::npos);
  const json c1 = FigureNamed(data, "conditions-run-1");
  ASSERT_TRUE(c1.is_object());
  EXPECT_NE(Section(html, 1).find("data-figure=\"conditions-run-1\""), std::string::npos);
  ASSERT_EQ(c1["series"].size(), 2u);
  EXPECT_EQ(c1["series"][0]["label"], "temperature (temp_c)");
  EXPECT_LE(c1["series"][0]["y"].size(), 40u);
  EXPECT_EQ(MaxOf(c1["series"][0]["y"]), 27.0);
  EXPECT_EQ(q1["frequency_over_run"], "freq_hz");
  EXPECT_EQ(q1["frequency_min_hz"], 4999.5);
  EXPECT_EQ(q1["frequency_max_hz"], 5000.0);
  EXPECT_EQ(q1["frequency_samples"], 200);
  EXPECT_NE(Section(html, 1).find("resonant frequency over the run [Hz]</td><td>"),
            std::string::npos);
  EXPECT_EQ(c1["series"][1]["label"], "resonant frequency (freq_hz)");
  EXPECT_EQ(c1["series"][1]["axis"], "y2");
  EXPECT_FALSE(c1["series"][1].contains("x"));  // on the run's decimated time axis
  EXPECT_LE(c1["series"][1]["y"].size(), 40u);
  EXPECT_EQ(MinOf(c1["series"][1]["y"]), 4999.5);
  EXPECT_EQ(MaxOf(c1["series"][1]["y"]), 5000.0);
  EXPECT_NE(c1["caption"].get<std::string>().find("from the run's freq_hz column"),
            std::string::npos);

  // Run 2: no temp_c column: the recorded ends, dashed, and the page says why.
  EXPECT_TRUE(data["derived"]["runs"]["2"]["temperature_over_run"].is_null());
  EXPECT_NE(Section(html, 2).find("the run CSV has no temp_c column"), std::string::npos);
  const json c2 = FigureNamed(data, "conditions-run-2");
  ASSERT_TRUE(c2.is_object());
  EXPECT_EQ(c2["series"][0]["label"], "temperature at start and end");
  EXPECT_EQ(c2["series"][0]["model"], true);
  EXPECT_NE(c2["caption"].get<std::string>().find("start and end only"), std::string::npos);
  EXPECT_TRUE(data["derived"]["runs"]["2"]["frequency_over_run"].is_null());
  EXPECT_NE(Section(html, 2).find("the run CSV has no freq_hz column"), std::string::npos);
  ASSERT_EQ(c2["series"].size(), 2u);
  EXPECT_EQ(c2["series"][1]["label"], "resonant frequency at start and end");
  EXPECT_EQ(c2["series"][1]["axis"], "y2");
  EXPECT_EQ(MaxOf(c2["series"][1]["y"]), 5000.01);

  // Run 3: nothing recorded: no figure, and the page says so.
  EXPECT_TRUE(FigureNamed(data, "conditions-run-3").is_null());
  EXPECT_NE(Section(html, 3).find("Figure conditions-run-3: not drawn"), std::string::npos);
  for (int run = 2; run <= 4; ++run)
    EXPECT_NE(Section(html, run).find("resonant frequency over the run [Hz]</td><td><span "
                                      "class=\"na\">not recorded</span>"),
              std::string::npos)
        << run;
}

}  // namespace
}  // namespace hrgbench::report
