// The serials of a fixture mapped onto its positions (fixture_session.hpp, PlanFixture), as the
// panel sends them (POSITION=SERIAL, one per fitted position): a position left empty on purpose
// ("C=") is not a unit of the session; every position left empty, a missing position and the
// operator id's rule (serial_check.hpp) are refused with the reason.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "app/fixture_session.hpp"
#include "app/serial_check.hpp"
#include "hrgbench/config/station_config.hpp"

namespace hrgbench::app {
namespace {

bench::StationConfig FixtureStation() {
  auto station = bench::LoadStationConfig(std::filesystem::path(HRGBENCH_SOURCE_DIR) /
                                          "bench_configs" / "station-sim-fixture.toml");
  EXPECT_TRUE(station) << (station ? "" : station.error().ToString());
  return station ? *station : bench::StationConfig{};
}

TEST(FixturePlan, APositionLeftEmptyIsNotAUnit) {
  const auto plan = PlanFixture(FixtureStation(), {"A=SN-1", "B=SN-2", "C=", "D=SN-4"});
  ASSERT_TRUE(plan) << plan.error();
  ASSERT_EQ(plan->units.size(), 3u);
  EXPECT_EQ(plan->units[0].position, "A");
  EXPECT_EQ(plan->units[1].position, "B");
  EXPECT_EQ(plan->units[2].position, "D");
  EXPECT_EQ(plan->units[2].folder, "D-SN-4");
}

TEST(FixturePlan, EveryPositionEmptyOrOneMissingIsRefused) {
  const auto none = PlanFixture(FixtureStation(), {"A=", "B=", "C=", "D="});
  ASSERT_FALSE(none);
  EXPECT_NE(none.error().find("every position is left empty"), std::string::npos) << none.error();
  const auto missing = PlanFixture(FixtureStation(), {"A=SN-1", "B=SN-2", "D=SN-4"});
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().find("position 'C'"), std::string::npos) << missing.error();
  const auto twice = PlanFixture(FixtureStation(), {"A=", "A=SN-1", "B=", "C=", "D="});
  ASSERT_FALSE(twice);
  EXPECT_NE(twice.error().find("given twice"), std::string::npos) << twice.error();
}

TEST(FixturePlan, AnOperatorIdFollowsTheSerialsRule) {
  EXPECT_FALSE(OperatorProblem("OP-17"));
  const auto bad = OperatorProblem("../x");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->rfind("the operator id", 0), 0u) << *bad;
  EXPECT_TRUE(OperatorProblem(""));
}

}  // namespace
}  // namespace hrgbench::app
