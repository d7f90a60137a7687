// The station file's [[fixture]]: the positions of the table's fixture, the interface of each, and
// on a simulated station each unit's truth over [simulated]'s (issue 12).
#include <gtest/gtest.h>

#include <string>

#include "hrgbench/config/station_config.hpp"

namespace {

using namespace hrgbench::bench;

const std::string kSimulated = R"([station]
name = "s"
kind = "simulated"

[site]
latitude_deg = 45.0

[simulated]
faster_than_real_time = true
seed = 7
sigma = 2e-4

[simulated.faults]
gyro_drop_every_nth_sample = 500
)";

const std::string kReal = R"([station]
name = "r"
kind = "real"

[site]
latitude_deg = 45.0

[gyro]

[table]
transport = "tcp"
host = "192.0.2.10"
)";

auto Parse(const std::string& text) { return ParseStationConfig(text, "s.toml"); }

TEST(StationFixture, WithoutFixtureTheStationHasOnePositionOnItsBus) {
  auto simulated = Parse(kSimulated);
  ASSERT_TRUE(simulated.has_value()) << simulated.error().ToString();
  ASSERT_EQ(simulated->fixture.size(), 1u);
  EXPECT_EQ(simulated->fixture[0].name, "1");
  EXPECT_EQ(simulated->fixture[0].can_interface, "vcan-sim");
  EXPECT_EQ(PositionSimulated(*simulated, simulated->fixture[0]).seed, 7u);

  std::string real = kReal;
  real.replace(real.find("[gyro]\n"), 7, "[gyro]\ncan_interface = \"can3\"\n");
  auto station = Parse(real);
  ASSERT_TRUE(station.has_value()) << station.error().ToString();
  ASSERT_EQ(FittedPositions(*station).size(), 1u);
  EXPECT_EQ(FittedPositions(*station)[0]->can_interface, "can3");
}

TEST(StationFixture, EachSimulatedUnitIsTheStationsWithItsOwnKeys) {
  auto station = Parse(kSimulated + R"(
[[fixture]]
position = "A"

[[fixture]]
position = "B"
delta = [-0.0008, 0.29, 3e-5, -2e-5, 2e-4, -1e-4]
xi = [-0.005, 0.003, 0.002, -0.004]
seed = 99
[fixture.faults]
gyro_stall_after_samples = 50
gyro_stall_from_run = 3

[[fixture]]
position = "empty-3"
fitted = false

[[fixture]]
position = "D_4"
sigma = 0.0
inverted = true
)");
  ASSERT_TRUE(station.has_value()) << station.error().ToString();
  ASSERT_EQ(station->fixture.size(), 4u);
  const auto fitted = FittedPositions(*station);
  ASSERT_EQ(fitted.size(), 3u);
  EXPECT_EQ(fitted[2]->name, "D_4");
  EXPECT_EQ(fitted[1]->can_interface, "vsim-B");
  EXPECT_FALSE(fitted[1]->inverted);
  EXPECT_TRUE(fitted[2]->inverted);

  const SimulatedStationConfig a = PositionSimulated(*station, *fitted[0]);
  EXPECT_EQ(a.seed, 7u);  // the first position's is [simulated]'s
  EXPECT_EQ(a.sigma, 2e-4);
  EXPECT_EQ(a.delta[1], 0.3);  // [simulated]'s default
  EXPECT_FALSE(a.faults.gyro_stall_after_samples.has_value());
  EXPECT_EQ(a.faults.gyro_drop_every_nth_sample, 500);

  const SimulatedStationConfig b = PositionSimulated(*station, *fitted[1]);
  EXPECT_EQ(b.seed, 99u);
  EXPECT_EQ(b.delta[4], 2e-4);
  EXPECT_EQ(b.xi[3], -0.004);
  EXPECT_EQ(b.sigma, 2e-4);
  EXPECT_EQ(b.faults.gyro_stall_after_samples, 50);
  EXPECT_EQ(b.faults.gyro_stall_from_run, 3);
  EXPECT_EQ(b.faults.gyro_drop_every_nth_sample, 500);  // the station's faults still apply

  // D is the fourth position declared: its seed is 7 + 3 × 1000, apart from every other unit's.
  const SimulatedStationConfig d = PositionSimulated(*station, *fitted[2]);
  EXPECT_EQ(d.seed, 3007u);
  EXPECT_EQ(d.sigma, 0.0);
}

TEST(StationFixture, RealPositionsNameTheirInterfaces) {
  auto station = Parse(kReal + R"(
[[fixture]]
position = "1"
can_interface = "can0"

[[fixture]]
position = "2"
can_interface = "can1"

[[fixture]]
position = "3"
can_interface = "can1"
fitted = false
)");
  ASSERT_TRUE(station.has_value()) << station.error().ToString();
  const auto fitted = FittedPositions(*station);
  ASSERT_EQ(fitted.size(), 2u);
  EXPECT_EQ(fitted[1]->can_interface, "can1");
}

struct BadFixture {
  const char* name;
  bool real;
  std::string text;
  std::size_t line;
  std::string key;
  std::string message;
};

class StationFixtureErrors : public ::testing::TestWithParam<BadFixture> {};

TEST_P(StationFixtureErrors, NameTheFileLineAndKey) {
  const BadFixture& bad = GetParam();
  auto station = Parse((bad.real ? kReal : kSimulated) + bad.text);
  ASSERT_FALSE(station.has_value()) << bad.name;
  const auto& error = station.error();
  EXPECT_EQ(error.file, "s.toml");
  EXPECT_EQ(error.line, bad.line) << error.ToString();
  EXPECT_EQ(error.key, bad.key) << error.ToString();
  EXPECT_NE(error.message.find(bad.message), std::string::npos) << error.ToString();
}

// kSimulated has 14 lines and kReal 12; the [[fixture]] text starts on the line after.
INSTANTIATE_TEST_SUITE_P(
    Cases, StationFixtureErrors,
    ::testing::Values(
        BadFixture{"twice", false, "[[fixture]]\nposition = \"A\"\n[[fixture]]\nposition = \"A\"\n",
                   18, "fixture[1].position", "declared twice"},
        BadFixture{"name", false, "[[fixture]]\nposition = \"A/B\"\n", 16, "fixture[0].position",
                   "letters, digits"},
        BadFixture{"shared bus", true,
                   "[[fixture]]\nposition = \"1\"\ncan_interface = \"can0\"\n[[fixture]]\n"
                   "position = \"2\"\ncan_interface = \"can0\"\n",
                   18, "fixture[1].can_node",
                   "positions '1' and '2' are both node 0 on can0; units on one bus need "
                   "distinct can_node ids"},
        BadFixture{"same node on a simulated bus", false,
                   "[[fixture]]\nposition = \"A\"\ncan_interface = \"vsim-1\"\ncan_node = 3\n"
                   "[[fixture]]\nposition = \"B\"\ncan_interface = \"vsim-1\"\ncan_node = 3\n",
                   22, "fixture[1].can_node", "both node 3 on vsim-1"},
        BadFixture{"node out of range", false, "[[fixture]]\nposition = \"A\"\ncan_node = 16\n", 17,
                   "fixture[0].can_node", "out of range"},
        BadFixture{"table fault", false,
                   "[[fixture]]\nposition = \"A\"\n[fixture.faults]\ntable_never_stable = true\n",
                   18, "fixture[0].faults.table_never_stable", "[simulated.faults]"},
        BadFixture{"none fitted", false, "[[fixture]]\nposition = \"A\"\nfitted = false\n", 15,
                   "fixture", "no position is fitted"},
        BadFixture{"unknown", false, "[[fixture]]\nposition = \"A\"\nslot = 3\n", 17,
                   "fixture[0].slot", "position, fitted"}),
    [](const auto& test) {
      std::string name = test.param.name;
      for (char& c : name)
        if (c == ' ') c = '_';
      return name;
    });

TEST(StationFixture, UnitsShareABusWithDistinctNodeIds) {
  auto real = Parse(kReal +
                    "[[fixture]]\nposition = \"A\"\ncan_interface = \"can0\"\ncan_node = 1\n"
                    "[[fixture]]\nposition = \"B\"\ncan_interface = \"can0\"\ncan_node = 2\n"
                    "[[fixture]]\nposition = \"C\"\ncan_interface = \"can1\"\ncan_node = 1\n"
                    // Not fitted: its node may repeat a fitted one's.
                    "[[fixture]]\nposition = \"D\"\ncan_interface = \"can0\"\ncan_node = 1\n"
                    "fitted = false\n");
  ASSERT_TRUE(real.has_value()) << real.error().ToString();
  const auto fitted = FittedPositions(*real);
  ASSERT_EQ(fitted.size(), 3u);
  EXPECT_EQ(fitted[0]->can_interface, "can0");
  EXPECT_EQ(fitted[0]->can_node, 1);
  EXPECT_EQ(fitted[1]->can_interface, "can0");
  EXPECT_EQ(fitted[1]->can_node, 2);
  EXPECT_EQ(fitted[2]->can_node, 1);

  // Simulated: the in-process bus's name; by default each position has its own.
  auto simulated = Parse(kSimulated +
                         "[[fixture]]\nposition = \"A\"\ncan_interface = \"vsim-AB\"\n"
                         "[[fixture]]\nposition = \"B\"\ncan_interface = \"vsim-AB\"\n"
                         "can_node = 5\n[[fixture]]\nposition = \"C\"\n");
  ASSERT_TRUE(simulated.has_value()) << simulated.error().ToString();
  EXPECT_EQ(simulated->fixture[0].can_interface, "vsim-AB");
  EXPECT_EQ(simulated->fixture[0].can_node, 0);
  EXPECT_EQ(simulated->fixture[1].can_interface, "vsim-AB");
  EXPECT_EQ(simulated->fixture[1].can_node, 5);
  EXPECT_EQ(simulated->fixture[2].can_interface, "vsim-C");
}

TEST(StationFixture, AStationOfOneUnitNamesItsNodeInTheGyroTable) {
  std::string real = kReal;
  real.replace(real.find("[gyro]\n"), 7, "[gyro]\ncan_interface = \"can3\"\ncan_node = 9\n");
  auto station = Parse(real);
  ASSERT_TRUE(station.has_value()) << station.error().ToString();
  EXPECT_EQ(FittedPositions(*station)[0]->can_node, 9);
  auto with_fixture = Parse(kReal + "[[fixture]]\nposition = \"1\"\ncan_interface = \"can0\"\n");
  ASSERT_TRUE(with_fixture.has_value());
  std::string both = kReal;
  both.replace(both.find("[gyro]\n"), 7, "[gyro]\ncan_node = 9\n");
  auto refused = Parse(both + "[[fixture]]\nposition = \"1\"\ncan_interface = \"can0\"\n");
  ASSERT_FALSE(refused.has_value());
  EXPECT_EQ(refused.error().key, "gyro.can_node");
  EXPECT_NE(refused.error().message.find("each position names its own can_node"), std::string::npos)
      << refused.error().ToString();
}

TEST(StationFixture, WithPositionsTheGyroTableNamesNoInterface) {
  std::string real = kReal;
  real.replace(real.find("[gyro]\n"), 7, "[gyro]\ncan_interface = \"can3\"\n");
  auto station = Parse(real + "[[fixture]]\nposition = \"1\"\ncan_interface = \"can0\"\n");
  ASSERT_FALSE(station.has_value());
  EXPECT_EQ(station.error().key, "gyro.can_interface");
  EXPECT_EQ(station.error().line, 9u);
  EXPECT_NE(station.error().message.find("each position names its own can_interface"),
            std::string::npos)
      << station.error().ToString();
}

TEST(StationFixture, FixtureIsAnArrayOfTables) {
  auto station = Parse("fixture = 3\n" + kSimulated);
  ASSERT_FALSE(station.has_value());
  EXPECT_EQ(station.error().key, "fixture");
  EXPECT_EQ(station.error().line, 1u);
  EXPECT_NE(station.error().message.find("[[fixture]] tables"), std::string::npos)
      << station.error().ToString();
}

TEST(StationFixture, AtMostSixteenPositions) {
  std::string text = kSimulated;
  for (int i = 0; i < 17; ++i) text += "[[fixture]]\nposition = \"P" + std::to_string(i) + "\"\n";
  auto station = Parse(text);
  ASSERT_FALSE(station.has_value());
  EXPECT_NE(station.error().message.find("a fixture has at most 16"), std::string::npos)
      << station.error().ToString();
}

}  // namespace
