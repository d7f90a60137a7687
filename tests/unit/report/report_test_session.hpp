#pragma once
// Sessions for the report tests, built here: simulated runs (SimulateRuns: closed-form model,
// seeded noise, δ and ξ below, four runs at Ω = 0.1, −0.3, 1, −1 rad/s, 2 s at 100 Hz) written with
// the session library's own writers, then damaged or extended as each test says. The page is
// checked against its contract (session_report.hpp) by reading the HTML text back with the
// helpers below.

#include <gtest/gtest.h>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "hrgbench/estimator/simulation.hpp"
#include "hrgbench/report/session_report.hpp"
#include "hrgbench/session/session.hpp"
#include "record_test_dir.hpp"
#include "required_tool.hpp"

namespace hrgbench::report::testing_support {

namespace fs = std::filesystem;
using json = nlohmann::json;

inline constexpr double kOmegas[] = {0.1, -0.3, 1.0, -1.0};

inline void WriteSession(const fs::path& dir, const json& extra = json::object()) {
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

inline ReportOptions Fast() {
  ReportOptions o;
  o.pdf = false;
  o.figures = false;
  return o;
}

inline std::string Read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

inline json SessionJson(const fs::path& dir) { return json::parse(Read(dir / "session.json")); }

inline json ReportData(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"report-data\">";
  const std::size_t at = html.find(open);
  EXPECT_NE(at, std::string::npos);
  EXPECT_EQ(html.find(open, at + 1), std::string::npos) << "one data block";
  const std::size_t begin = at + open.size();
  return json::parse(html.substr(begin, html.find("</script>", begin) - begin));
}

// The text of run N's section ("" when there is none).
inline std::string Section(const std::string& html, int run) {
  const std::string open = "<section class=\"run\" id=\"run-" + std::to_string(run) + "\"";
  const std::size_t at = html.find(open);
  if (at == std::string::npos) return {};
  return html.substr(at, html.find("</section>", at) - at);
}

inline std::string Top(const std::string& html) {
  return html.substr(0, html.find("<section class=\"run\""));
}

inline double Parse(const std::string& text) {
  double v = std::nan("");
  std::from_chars(text.data(), text.data() + text.size(), v);
  return v;
}

// Every data-source resolves in session.json to the number in data-value (exactly: shortest
// round-trip text), every data-derived in the data block. Returns how many were checked.
inline int CheckNumbers(const std::string& html, const json& session, const json& data) {
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

inline bool OnPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  std::string d;
  while (std::getline(dirs, d, ':'))
    if (!d.empty() && ::access((fs::path(d) / program).c_str(), X_OK) == 0) return true;
  return false;
}

inline json RecordedOutcome() {
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

}  // namespace hrgbench::report::testing_support
