// The station keys of a run's Ω (bench_configs/README.md): [table] omega_source, which
// measurement the estimator gets, and the simulated table's encoder ([simulated]
// table_encoder_counts_per_rev, table_encoder_noise_rad). Strict and bounded like every key: an
// error names file, line, key and value.
#include <gtest/gtest.h>

#include <string>

#include "hrgbench/config/station_config.hpp"

namespace hrgbench::bench {
namespace {

const std::filesystem::path kFile = "bench_configs/station.toml";

const std::string kSimulated = R"([station]
name = "s"
kind = "simulated"
[site]
latitude_deg = 45.0
[simulated]
faster_than_real_time = true
)";

std::string WithTable(const std::string& table_line) {
  return R"([station]
name = "s"
kind = "simulated"
[site]
latitude_deg = 45.0
[table]
)" + table_line +
         "\n[simulated]\nfaster_than_real_time = true\n";
}

TEST(StationTableOmega, AbsentMeansTheAngleWhenTheTableReportsOne) {
  auto station = ParseStationConfig(kSimulated, kFile);
  ASSERT_TRUE(station) << station.error().ToString();
  EXPECT_EQ(station->table.omega_source, OmegaSourceSetting::kAngleWhenReported);
  EXPECT_EQ(ToString(station->table.omega_source), "angle when reported");
  EXPECT_EQ(station->simulated.table_encoder_counts_per_rev, 8388608);
  EXPECT_EQ(station->simulated.table_encoder_noise_rad, 1e-6);
}

TEST(StationTableOmega, AngleAndRateAreTheValues) {
  auto angle = ParseStationConfig(WithTable("omega_source = \"angle\""), kFile);
  ASSERT_TRUE(angle) << angle.error().ToString();
  EXPECT_EQ(angle->table.omega_source, OmegaSourceSetting::kAngle);
  auto rate = ParseStationConfig(WithTable("omega_source = \"rate\""), kFile);
  ASSERT_TRUE(rate) << rate.error().ToString();
  EXPECT_EQ(rate->table.omega_source, OmegaSourceSetting::kRate);
}

TEST(StationTableOmega, AnythingElseIsAnErrorNamingFileLineKeyAndValue) {
  for (const char* value : {"\"Angle\"", "\"encoder\"", "\"\"", "\"angle when reported\""}) {
    auto station = ParseStationConfig(WithTable(std::string("omega_source = ") + value), kFile);
    ASSERT_FALSE(station) << value;
    const auto& e = station.error();
    EXPECT_EQ(e.file, kFile);
    EXPECT_EQ(e.line, 7u) << e.ToString();
    EXPECT_EQ(e.key, "table.omega_source") << e.ToString();
    EXPECT_EQ(e.value, value) << e.ToString();
    EXPECT_NE(e.message.find("one of"), std::string::npos) << e.ToString();
  }
  auto number = ParseStationConfig(WithTable("omega_source = 1"), kFile);
  ASSERT_FALSE(number);
  EXPECT_NE(number.error().message.find("wrong type"), std::string::npos)
      << number.error().ToString();
  auto misspelt = ParseStationConfig(WithTable("omega_sources = \"angle\""), kFile);
  ASSERT_FALSE(misspelt);
  EXPECT_EQ(misspelt.error().key, "table.omega_sources") << misspelt.error().ToString();
}

TEST(StationTableOmega, TheSimulatedEncoderIsBounded) {
  auto ok = ParseStationConfig(
      kSimulated + "table_encoder_counts_per_rev = 36000000\ntable_encoder_noise_rad = 0.0\n",
      kFile);
  ASSERT_TRUE(ok) << ok.error().ToString();
  EXPECT_EQ(ok->simulated.table_encoder_counts_per_rev, 36000000);
  EXPECT_EQ(ok->simulated.table_encoder_noise_rad, 0.0);
  struct Case {
    const char* line;
    const char* key;
  };
  for (const Case& c :
       {Case{"table_encoder_counts_per_rev = 4095", "table_encoder_counts_per_rev"},
        Case{"table_encoder_counts_per_rev = 2147483649", "table_encoder_counts_per_rev"},
        Case{"table_encoder_counts_per_rev = 1.5", "table_encoder_counts_per_rev"},
        Case{"table_encoder_noise_rad = -1e-6", "table_encoder_noise_rad"},
        Case{"table_encoder_noise_rad = 0.01", "table_encoder_noise_rad"},
        Case{"table_encoder_noise_rad = nan", "table_encoder_noise_rad"}}) {
    auto station = ParseStationConfig(kSimulated + c.line + "\n", kFile);
    ASSERT_FALSE(station) << c.line;
    EXPECT_EQ(station.error().line, 8u) << station.error().ToString();
    EXPECT_EQ(station.error().key, std::string("simulated.") + c.key) << station.error().ToString();
  }
}

}  // namespace
}  // namespace hrgbench::bench
