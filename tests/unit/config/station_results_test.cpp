// The station file's [results] table: where hrg-bench uploads closed sessions (issue 10).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "hrgbench/config/station_config.hpp"

namespace {

using namespace hrgbench::bench;

const std::string kBase = R"([station]
name = "s"
kind = "simulated"

[site]
latitude_deg = 45.0

[simulated]
faster_than_real_time = true
)";

TEST(StationResults, AbsentMeansNoUploadAndTheShippedSimStationUsesSqliteUnderBuildOut) {
  auto none = ParseStationConfig(kBase, "s.toml");
  ASSERT_TRUE(none.has_value()) << none.error().ToString();
  EXPECT_TRUE(none->results_url.empty());
  auto shipped =
      LoadStationConfig(std::string(HRGBENCH_SOURCE_DIR) + "/bench_configs/station-sim.toml");
  ASSERT_TRUE(shipped.has_value()) << shipped.error().ToString();
  // Relative to the station file's folder, not to the working directory (issue 26).
  EXPECT_EQ(shipped->results_url,
            "sqlite://" + (std::filesystem::path(HRGBENCH_SOURCE_DIR) / "build/out/results.sqlite")
                              .lexically_normal()
                              .string());
  EXPECT_TRUE(shipped->results_url_relative);
}

// hrg-results --station run from another folder once read (and created) an empty database there.
TEST(StationResults, ARelativeSqlitePathIsTakenFromTheStationFilesFolder) {
  const std::filesystem::path folder = std::filesystem::temp_directory_path() /
                                       ("hrgbench-station-url-" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder / "line");
  const std::filesystem::path file = folder / "line" / "station.toml";
  std::ofstream(file) << kBase << "\n[results]\nurl = \"sqlite://store/r.sqlite\"\n";
  auto loaded = LoadStationConfig(file);
  ASSERT_TRUE(loaded.has_value()) << loaded.error().ToString();
  EXPECT_EQ(loaded->results_url, "sqlite://" + (folder / "line" / "store" / "r.sqlite").string());
  // From text there is no folder: the path stays as written (the working directory's).
  auto parsed =
      ParseStationConfig(kBase + "\n[results]\nurl = \"sqlite://store/r.sqlite\"\n", file);
  ASSERT_TRUE(parsed.has_value());
  EXPECT_EQ(parsed->results_url, "sqlite://store/r.sqlite");
  // An absolute path and a server are kept.
  std::ofstream(file) << kBase << "\n[results]\nurl = \"sqlite:///srv/r.sqlite\"\n";
  EXPECT_EQ(LoadStationConfig(file)->results_url, "sqlite:///srv/r.sqlite");
  std::error_code ec;
  std::filesystem::remove_all(folder, ec);
}

TEST(StationResults, PostgresqlUrlIsKept) {
  auto station = ParseStationConfig(
      kBase + "\n[results]\nurl = \"postgresql://station@db.line/results?sslmode=verify-full\"\n",
      "s.toml");
  ASSERT_TRUE(station.has_value()) << station.error().ToString();
  EXPECT_EQ(station->results_url, "postgresql://station@db.line/results?sslmode=verify-full");
}

TEST(StationResults, APasswordIsRefusedByLineWithoutShowingIt) {
  auto station = ParseStationConfig(
      kBase + "\n[results]\nurl = \"postgresql://station:hunter2@db.line/results\"\n", "s.toml");
  ASSERT_FALSE(station.has_value());
  const std::string text = station.error().ToString();
  EXPECT_EQ(station.error().key, "results.url");
  EXPECT_EQ(station.error().line, 12u);  // kBase is 9 lines, a blank, [results]
  EXPECT_NE(text.find("password"), std::string::npos) << text;
  EXPECT_EQ(text.find("hunter2"), std::string::npos) << text;
}

TEST(StationResults, TyposAndUnknownKeysAreErrors) {
  auto scheme = ParseStationConfig(kBase + "\n[results]\nurl = \"sqllite:///x.db\"\n", "s.toml");
  ASSERT_FALSE(scheme.has_value());
  EXPECT_NE(scheme.error().message.find("unknown scheme"), std::string::npos)
      << scheme.error().ToString();
  auto key =
      ParseStationConfig(kBase + "\n[results]\nurl = \"sqlite:///x.db\"\nuser = \"a\"\n", "s.toml");
  ASSERT_FALSE(key.has_value());
  EXPECT_EQ(key.error().key, "results.user");
  auto missing = ParseStationConfig(kBase + "\n[results]\n", "s.toml");
  ASSERT_FALSE(missing.has_value());
  EXPECT_EQ(missing.error().key, "results.url");
}

}  // namespace
