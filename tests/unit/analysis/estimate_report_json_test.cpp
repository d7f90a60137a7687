#include "hrgbench/analysis/estimate_report_json.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "hand_made_record.hpp"
#include "hrgbench/analysis/recorded_frequency.hpp"

namespace hrgbench::bench {
namespace {

using estimator::EstimateSummary;
using estimator::kNaN;
using testing::RecordOf;

// What an ML fit with ξ1 only estimated returns.
EstimateSummary Xi1Summary() {
  EstimateSummary s;
  s.method = "maximum likelihood";
  s.termination = estimator::Termination::kConverged;
  s.message = "converged";
  s.delta << -0.001, 0.3, 1e-9, -1e-9, 2e-9, 0.0;
  s.delta_std << 1e-7, 1e-3, 1e-7, 1e-7, 1e-7, 1e-7;
  s.delta_estimated = {true, true, true, true, true, true};
  s.xi << 0.01, 0.0, 0.0, 0.0;
  s.xi_std << 1e-4, kNaN, kNaN, kNaN;
  s.xi_estimated = estimator::kXi1Only;
  s.residual_rms_per_run = {1e-4, 1.1e-4};
  s.residual_rms = 1.05e-4;
  s.noise_sigma = 1.06e-4;
  s.iterations = 4;
  s.samples_used = 2002;
  s.warnings = {"estimator warning"};
  return s;
}

std::set<std::string> Keys(const nlohmann::json& j) {
  std::set<std::string> keys;
  for (const auto& [key, value] : j.items()) keys.insert(key);
  return keys;
}

std::set<std::string> RequiredKeys() {
  std::set<std::string> keys;
  for (std::string_view k : kReportKeys) keys.insert(std::string(k));
  return keys;
}

void ExpectNumbers(const nlohmann::json& j, std::size_t n, const char* what) {
  ASSERT_TRUE(j.is_array()) << what;
  ASSERT_EQ(j.size(), n) << what;
  for (const auto& v : j) EXPECT_TRUE(v.is_number()) << what << ": " << v;
}

TEST(EstimateReportJson, HasExactlyTheDocumentedKeysAndTypes) {
  const nlohmann::json j = EstimateReportJson("ml", Xi1Summary(), {"selection warning"},
                                              RecordOf(nlohmann::json::object()));
  EXPECT_EQ(Keys(j), RequiredKeys());
  EXPECT_EQ(j["method"], "ml");
  ExpectNumbers(j["delta"], 6, "delta");
  ExpectNumbers(j["delta_std"], 6, "delta_std");
  ExpectNumbers(j["xi"], 4, "xi");
  ASSERT_TRUE(j["xi_std"].is_array());
  ASSERT_EQ(j["xi_std"].size(), 4u);
  EXPECT_TRUE(j["xi_std"][0].is_number());
  for (int i = 1; i < 4; ++i) EXPECT_TRUE(j["xi_std"][i].is_null()) << "xi_std[" << i << "]";
  EXPECT_TRUE(j["residual_rms"].is_number());
  EXPECT_TRUE(j["converged"].is_boolean());
  EXPECT_TRUE(j["converged"].get<bool>());
  ASSERT_TRUE(j["warnings"].is_array());
  for (const auto& w : j["warnings"]) EXPECT_TRUE(w.is_string());
  EXPECT_EQ(j["warnings"], (nlohmann::json{"selection warning", "estimator warning"}));
  EXPECT_TRUE(j["termination"].is_string());
  EXPECT_TRUE(j["message"].is_string());
  EXPECT_TRUE(j["iterations"].is_number_integer());
  EXPECT_TRUE(j["samples_used"].is_number_integer());
  ExpectNumbers(j["residual_rms_per_run"], 2, "residual_rms_per_run");
  EXPECT_TRUE(j["noise_sigma"].is_number());
  EXPECT_EQ(j["delta"][1].get<double>(), 0.3);
  EXPECT_EQ(j["xi"][0].get<double>(), 0.01);
}

TEST(EstimateReportJson, HeldDeltaHasNullStd) {
  EstimateSummary s = Xi1Summary();
  s.delta_estimated[estimator::kScaleFactor] = false;
  const nlohmann::json j = EstimateReportJson("ml", s, {}, RecordOf(nlohmann::json::object()));
  EXPECT_TRUE(j["delta_std"][1].is_null());
  EXPECT_TRUE(j["delta"][1].is_number());  // the held value is still reported
}

TEST(EstimateReportJson, NonFiniteNumbersAreNull) {
  EstimateSummary s;  // "not called": everything NaN
  s.termination = estimator::Termination::kNumericalFailure;
  const nlohmann::json j = EstimateReportJson("paper", s, {}, RecordOf(nlohmann::json::object()));
  EXPECT_EQ(Keys(j), RequiredKeys());
  EXPECT_TRUE(j["residual_rms"].is_null());
  EXPECT_TRUE(j["noise_sigma"].is_null());
  for (const auto& v : j["delta"]) EXPECT_TRUE(v.is_null());
  for (const auto& v : j["xi_std"]) EXPECT_TRUE(v.is_null());
  EXPECT_FALSE(j["converged"].get<bool>());
  // And the dump is valid JSON (no NaN literal).
  EXPECT_TRUE(nlohmann::json::accept(j.dump()));
}

TEST(EstimateReportJson, TruthFromTheSessionsSimulationBlock) {
  const nlohmann::json document = {{"format", "hrgbench-session"},
                                   {"simulation",
                                    {{"delta", {-0.001, 0.3, 0, 0, 0, 0}},
                                     {"xi", {0.01, 0, 0, 0}},
                                     {"sigma", 0.0},
                                     {"seed", 12345},
                                     {"generator", "test"},
                                     {"runs", nlohmann::json::array()}}}};
  const nlohmann::json j = EstimateReportJson("ml", Xi1Summary(), {}, RecordOf(document));
  std::set<std::string> expected = RequiredKeys();
  expected.insert("truth");
  EXPECT_EQ(Keys(j), expected);
  EXPECT_EQ(Keys(j["truth"]), (std::set<std::string>{"delta", "xi", "sigma", "seed"}));
  EXPECT_EQ(j["truth"]["delta"][1].get<double>(), 0.3);
}

// The engineering quantities, with f0 the mean of the complete runs' recorded resonant frequency
// (an aborted run's and a missing value are not counted).
TEST(EstimateReportJson, CarriesTheEngineeringQuantitiesWithTheRecordedFrequency) {
  const nlohmann::json document = nlohmann::json::parse(R"({"runs": [
      {"id": 1, "status": "complete", "start": {"resonant_frequency_hz": 5000.002}},
      {"id": 2, "status": "aborted", "start": {"resonant_frequency_hz": 4000.0}},
      {"id": 3, "status": "complete", "start": {"resonant_frequency_hz": null}},
      {"id": 4, "status": "complete", "start": {"resonant_frequency_hz": 5000.004}}]})");
  const session::SessionRecord record = RecordOf(document);
  const RecordedFrequency f0 = RecordedResonantFrequency(record);
  EXPECT_EQ(f0.runs, 2);
  EXPECT_DOUBLE_EQ(f0.hz, 5000.003);
  EXPECT_NEAR(f0.spread_hz, 0.002, 1e-9);

  const nlohmann::json j = EstimateReportJson("ml", Xi1Summary(), {}, record);
  const nlohmann::json& e = j["engineering"];
  EXPECT_DOUBLE_EQ(e["frequency_hz"].get<double>(), 5000.003);
  EXPECT_NE(e["frequency_source"].get<std::string>().find("2 runs"), std::string::npos);
  ASSERT_EQ(e["quantities"].size(), estimator::kEngineeringQuantityCount);
  const nlohmann::json& tau = e["quantities"][1];
  EXPECT_EQ(tau["name"], "tau_s");
  EXPECT_EQ(tau["unit"], "s");
  EXPECT_DOUBLE_EQ(tau["value"].get<double>(), 1000.0);  // −1/δ1
  EXPECT_EQ(tau["determined"], true);
  const nlohmann::json& q = e["quantities"][2];
  EXPECT_NEAR(q["value"].get<double>(), 3.14159265358979 * 5000.003 * 1000.0, 1.0);
  // ξ3 was held: the cross-talk is its image, not a measurement.
  const nlohmann::json& cross_talk = e["quantities"][12];
  EXPECT_EQ(cross_talk["name"], "cross_talk_percent");
  EXPECT_EQ(cross_talk["determined"], false);
  EXPECT_TRUE(cross_talk["std"].is_null());

  const nlohmann::json none =
      EstimateReportJson("ml", Xi1Summary(), {}, RecordOf(nlohmann::json::object()));
  EXPECT_TRUE(none["engineering"]["frequency_hz"].is_null());
  EXPECT_EQ(none["engineering"]["quantities"][2]["determined"], false);  // Q without f0
}

}  // namespace
}  // namespace hrgbench::bench
