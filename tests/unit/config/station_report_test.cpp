// The station file's [report] table: the sheet of the session report's PDF (issue 26 §4: A4 and
// Letter). Strict: the error names the file, the key and the value.
#include <gtest/gtest.h>

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

TEST(StationReport, PaperIsA4UnlessTheStationSaysLetter) {
  auto none = ParseStationConfig(kBase, "s.toml");
  ASSERT_TRUE(none.has_value()) << none.error().ToString();
  EXPECT_EQ(none->report_paper, "a4");
  auto letter = ParseStationConfig(kBase + "\n[report]\npaper = \"Letter\"\n", "s.toml");
  ASSERT_TRUE(letter.has_value()) << letter.error().ToString();
  EXPECT_EQ(letter->report_paper, "letter");
  auto a4 = ParseStationConfig(kBase + "\n[report]\npaper = \"A4\"\n", "s.toml");
  ASSERT_TRUE(a4.has_value()) << a4.error().ToString();
  EXPECT_EQ(a4->report_paper, "a4");
}

TEST(StationReport, AnUnknownSheetOrKeyIsAnErrorNamingFileKeyAndValue) {
  auto legal = ParseStationConfig(kBase + "\n[report]\npaper = \"Legal\"\n", "line/s.toml");
  ASSERT_FALSE(legal.has_value());
  EXPECT_EQ(legal.error().file, "line/s.toml");
  EXPECT_EQ(legal.error().key, "report.paper");
  EXPECT_EQ(legal.error().value, "\"Legal\"");
  EXPECT_NE(legal.error().message.find("\"A4\" or \"Letter\""), std::string::npos);
  EXPECT_GT(legal.error().line, 0u);

  auto unknown =
      ParseStationConfig(kBase + "\n[report]\npaper = \"A4\"\nmargin_mm = 12\n", "s.toml");
  ASSERT_FALSE(unknown.has_value());
  EXPECT_EQ(unknown.error().key, "report.margin_mm");

  auto missing = ParseStationConfig(kBase + "\n[report]\n", "s.toml");
  ASSERT_FALSE(missing.has_value());
  EXPECT_EQ(missing.error().key, "report.paper");

  auto typed = ParseStationConfig(kBase + "\n[report]\npaper = 4\n", "s.toml");
  ASSERT_FALSE(typed.has_value());
  EXPECT_EQ(typed.error().key, "report.paper");
}

}  // namespace
