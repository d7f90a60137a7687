// The station's [gyro] pick-off declaration (pickoff_cross_talk_stage, pickoff_coupling_bound_rad:
// what free runs cannot measure of the pick-off, session/electronics.hpp): defaults, the values
// loaded and recorded, bad values named by key and value; and the engineering quantities of a
// record (engineering_of_record.hpp) reading it back through the record's one reader
// (session::ReadSessionRecord): the budget follows the declaration, a record without one is read
// as the default with a note, a bad one is refused by field and value.

#include <gtest/gtest.h>

#include <string>

#include "hand_made_record.hpp"
#include "hrgbench/analysis/engineering_of_record.hpp"
#include "hrgbench/config/bench_configs.hpp"
#include "hrgbench/config/station_config.hpp"
#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/simulation.hpp"

namespace hrgbench::bench {
namespace {

using estimator::CrossTalkStage;
using Q = estimator::EngineeringQuantity;
using testing::CompleteSessionDocument;
using testing::RecordOf;

// What the record's reader says of a hand-made document (completed to what it requires).
std::expected<session::SessionRecord, session::SessionError> Read(const nlohmann::json& partial) {
  return session::ReadSessionRecord(CompleteSessionDocument(partial), "test/session.json");
}

std::string Station(const std::string& gyro_keys) {
  return "[station]\nname = \"x\"\nkind = \"simulated\"\n[site]\nlatitude_deg = 45.0\n"
         "axis_enu = [0.0, 0.0, 1.0]\n[gyro]\n" +
         gyro_keys + "[simulated]\n";
}

TEST(StationPickoff, AbsentMeansMidwayAndNoBound) {
  auto station = ParseStationConfig(Station(""), "s.toml");
  ASSERT_TRUE(station.has_value()) << station.error().ToString();
  EXPECT_EQ(station->gyro.pickoff.cross_talk_stage, CrossTalkStage::kMidway);
  EXPECT_EQ(station->gyro.pickoff.unmodelled_coupling_bound_rad, 0.0);
}

TEST(StationPickoff, TheDeclarationIsLoadedAndReadsBackFromTheRecord) {
  auto station = ParseStationConfig(
      Station("pickoff_cross_talk_stage = \"after_gain\"\npickoff_coupling_bound_rad = 2e-4\n"),
      "s.toml");
  ASSERT_TRUE(station.has_value()) << station.error().ToString();
  EXPECT_EQ(station->gyro.pickoff.cross_talk_stage, CrossTalkStage::kAfterGain);
  EXPECT_EQ(station->gyro.pickoff.unmodelled_coupling_bound_rad, 2e-4);
  const nlohmann::json doc = {
      {"electronics", {{"pickoff", PickoffDeclarationJson(station->gyro.pickoff)}}}};
  const RecordedPickoff back = RecordedPickoffDeclaration(RecordOf(doc).electronics);
  EXPECT_EQ(back.declaration.cross_talk_stage, CrossTalkStage::kAfterGain);
  EXPECT_EQ(back.declaration.unmodelled_coupling_bound_rad, 2e-4);
  EXPECT_TRUE(back.note.empty());
  // Every stage the writer spells, the reader reads (the session layer spells the names itself).
  for (const CrossTalkStage stage :
       {CrossTalkStage::kMidway, CrossTalkStage::kBeforeGain, CrossTalkStage::kAfterGain}) {
    const session::SessionRecord record =
        RecordOf({{"electronics", {{"pickoff", PickoffDeclarationJson({stage, 0.0})}}}});
    ASSERT_TRUE(record.electronics.pickoff.has_value()) << estimator::ToString(stage);
    EXPECT_EQ(record.electronics.pickoff->cross_talk_stage, stage);
  }
}

TEST(StationPickoff, BadValuesNameTheKeyAndValue) {
  for (const std::string& keys : {std::string("pickoff_cross_talk_stage = \"inside\"\n"),
                                  std::string("pickoff_coupling_bound_rad = -1e-3\n"),
                                  std::string("pickoff_coupling_bound_rad = 0.5\n")}) {
    auto station = ParseStationConfig(Station(keys), "s.toml");
    ASSERT_FALSE(station.has_value()) << keys;
    const std::string text = station.error().ToString();
    EXPECT_NE(text.find(keys.substr(0, keys.find(' '))), std::string::npos) << text;
    EXPECT_NE(text.find("s.toml"), std::string::npos) << text;
  }
  const auto bad_stage = Read({{"electronics", {{"pickoff", {{"cross_talk_stage", "inside"}}}}}});
  ASSERT_FALSE(bad_stage.has_value());
  EXPECT_NE(bad_stage.error().ToString().find("electronics.pickoff.cross_talk_stage"),
            std::string::npos);
  EXPECT_NE(bad_stage.error().ToString().find("\"inside\""), std::string::npos);
  const auto bad_bound =
      Read({{"electronics", {{"pickoff", {{"unmodelled_coupling_bound_rad", "big"}}}}}});
  ASSERT_FALSE(bad_bound.has_value());
  EXPECT_NE(bad_bound.error().ToString().find("unmodelled_coupling_bound_rad"), std::string::npos);
}

// A record's declaration reaches the budget: a declared stage carries no stage component; a
// declared bound evaluates the unmodelled coupling; a record without a declaration is read as
// midway with a note; the runs' f0 spread is f0's component of Q.
TEST(EngineeringOfRecord, TheBudgetFollowsTheRecordsDeclaration) {
  estimator::SimulationOptions truth;
  truth.delta << -1e-3, 0.3, 2e-5, -1e-5, 3e-4, -2e-4;
  truth.xi << 0.01, -0.003, 0.002, 0.004;
  truth.sigma = 1e-4;
  truth.seed = 3;
  std::vector<estimator::RunPlan> plans;
  const double omegas[4] = {0.3, -0.3, 1.0, -1.0};
  for (int k = 0; k < 4; ++k) {
    estimator::RunPlan p;
    p.omega_rad_s = omegas[k];
    p.a = 1.0;
    p.b = 0.1;
    p.theta_rad = 0.3 * k;
    p.sample_rate_hz = 100.0;
    p.duration_s = 10.0;
    plans.push_back(p);
  }
  const estimator::EstimateSummary s =
      estimator::EstimateMaximumLikelihood(estimator::SimulateRuns(plans, truth));
  ASSERT_TRUE(s.IsUsable()) << s.Report();
  const auto component = [](const estimator::EngineeringValue& v, std::string_view source) {
    for (const estimator::UncertaintyComponent& c : v.budget)
      if (c.source == source) return c.standard_uncertainty;
    return -1.0;  // absent
  };
  nlohmann::json doc = {{"runs", nlohmann::json::array()}};
  for (double f0 : {5000.0, 5000.012})
    doc["runs"].push_back({{"status", "complete"}, {"start", {{"resonant_frequency_hz", f0}}}});

  const EngineeringOfRecord undeclared = ComputeEngineeringOfRecord(s, RecordOf(doc));
  ASSERT_EQ(undeclared.notes.size(), 1u);
  const estimator::EngineeringValue& axis = undeclared.quantities[Q::kFrequencyAxis];
  EXPECT_GT(component(axis, "pick-off model: cross-talk stage"), 0.0);
  EXPECT_TRUE(std::isnan(component(axis, "pick-off model: unmodelled antisymmetric coupling")));
  // Q's f0 component: the spread 0.012 Hz over √12, times Q/f0.
  const estimator::EngineeringValue& q = undeclared.quantities[Q::kQualityFactor];
  EXPECT_NEAR(component(q, "f0 as reported"), q.value / 5000.006 * 0.012 / std::sqrt(12.0),
              1e-6 * q.value);

  doc["electronics"]["pickoff"] = PickoffDeclarationJson({CrossTalkStage::kBeforeGain, 1e-3});
  const EngineeringOfRecord declared = ComputeEngineeringOfRecord(s, RecordOf(doc));
  EXPECT_TRUE(declared.notes.empty());
  const estimator::EngineeringValue& declared_axis = declared.quantities[Q::kFrequencyAxis];
  EXPECT_EQ(component(declared_axis, "pick-off model: cross-talk stage"), 0.0);
  EXPECT_GT(component(declared_axis, "pick-off model: unmodelled antisymmetric coupling"), 0.0);
}

}  // namespace
}  // namespace hrgbench::bench
