// What the panel offers: the sequence-* and limits-* files beside the station that load with it,
// in name order; a broken one is left out, not fatal; no sequence at all is an error. And the
// session names the page may ask a report of.
#include "app/panel/panel_catalog.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

namespace hrgbench::app {
namespace {

namespace fs = std::filesystem;
const fs::path kConfigs = fs::path(HRGBENCH_SOURCE_DIR) / "bench_configs";

fs::path FreshDir() {
  std::random_device rd;
  const fs::path dir = fs::temp_directory_path() / ("hrgbench-catalog-" + std::to_string(rd()));
  fs::create_directories(dir);
  return dir;
}

// The shipped simulated station copied to `to`, without its [offers] (or with `offers` instead).
void CopyStation(const fs::path& to, const std::string& offers = "") {
  std::ifstream in(kConfigs / "station-sim.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::string toml = text.str();
  toml = toml.substr(0, toml.find("\n[offers]"));
  std::ofstream(to) << toml << '\n' << offers;
}

TEST(PanelCatalog, OffersTheFilesBesideTheStationThatLoad) {
  const fs::path dir = FreshDir();
  CopyStation(dir / "station.toml");
  fs::copy_file(kConfigs / "sequence-paper.toml", dir / "sequence-b.toml");
  fs::copy_file(kConfigs / "sequence-production.toml", dir / "sequence-a.toml");
  std::ofstream(dir / "sequence-broken.toml") << "[sequence]\nname = \"x\"\nbogus = 1\n";
  fs::copy_file(kConfigs / "limits-example.toml", dir / "limits-example.toml");
  fs::copy_file(kConfigs / "limits-example.toml", dir / "other-limits.toml");  // not limits-*
  auto catalog = LoadPanelCatalog(dir / "station.toml");
  ASSERT_TRUE(catalog) << catalog.error();
  ASSERT_EQ(catalog->sequences.size(), 2u);
  EXPECT_EQ(catalog->sequences[0].file.filename(), "sequence-a.toml");
  EXPECT_EQ(catalog->sequences[1].file.filename(), "sequence-b.toml");
  ASSERT_EQ(catalog->limits.size(), 1u);
  EXPECT_EQ(catalog->limits[0].name, "example");
  fs::remove_all(dir);
}

TEST(PanelCatalog, NoSequenceIsAnErrorNamingTheStation) {
  const fs::path dir = FreshDir();
  CopyStation(dir / "station.toml");
  auto catalog = LoadPanelCatalog(dir / "station.toml");
  ASSERT_FALSE(catalog);
  EXPECT_NE(catalog.error().find("station.toml"), std::string::npos) << catalog.error();
  fs::remove_all(dir);
}

// Issue 26 §1: the station says what it offers, in its order, and its defaults (the page selects
// them, never merely the first by name); a name with no file is refused naming key and value;
// "no limits" only when declared, and a real station never offers it.
TEST(PanelCatalog, TheStationsOffersAndDefaultsAreWhatIsOffered) {
  const fs::path dir = FreshDir();
  fs::copy_file(kConfigs / "sequence-paper.toml", dir / "sequence-paper.toml");
  fs::copy_file(kConfigs / "sequence-production.toml", dir / "sequence-production.toml");
  fs::copy_file(kConfigs / "limits-example.toml", dir / "limits-example.toml");
  fs::copy_file(kConfigs / "limits-example.toml", dir / "limits-other.toml");
  CopyStation(dir / "station.toml",
              "[offers]\nsequences = [\"sequence-paper.toml\", \"sequence-production.toml\"]\n"
              "default_sequence = \"sequence-production.toml\"\n"
              "limits = [\"limits-other.toml\", \"limits-example.toml\"]\n"
              "default_limits = \"limits-example.toml\"\n");
  auto catalog = LoadPanelCatalog(dir / "station.toml");
  ASSERT_TRUE(catalog) << catalog.error();
  ASSERT_EQ(catalog->sequences.size(), 2u);
  EXPECT_EQ(catalog->sequences[catalog->default_sequence].file.filename(),
            "sequence-production.toml");
  ASSERT_EQ(catalog->limits.size(), 2u);
  EXPECT_EQ(catalog->limits[catalog->default_limits].file.filename(), "limits-example.toml");
  EXPECT_FALSE(catalog->no_limits);

  CopyStation(dir / "station.toml", "[offers]\ndefault_sequence = \"sequence-nothere.toml\"\n");
  catalog = LoadPanelCatalog(dir / "station.toml");
  ASSERT_FALSE(catalog);
  EXPECT_NE(catalog.error().find("default_sequence = \"sequence-nothere.toml\": no such file"),
            std::string::npos)
      << catalog.error();

  CopyStation(dir / "station.toml",
              "[offers]\nsequences = [\"sequence-paper.toml\"]\n"
              "default_sequence = \"sequence-production.toml\"\n");
  catalog = LoadPanelCatalog(dir / "station.toml");
  ASSERT_FALSE(catalog);
  EXPECT_NE(catalog.error().find("default_sequence"), std::string::npos) << catalog.error();
  EXPECT_NE(catalog.error().find("not one of sequences"), std::string::npos) << catalog.error();

  CopyStation(dir / "station.toml", "[offers]\nno_limits = true\n");
  catalog = LoadPanelCatalog(dir / "station.toml");
  ASSERT_TRUE(catalog) << catalog.error();
  EXPECT_TRUE(catalog->no_limits);
  fs::remove_all(dir);
}

TEST(PanelCatalog, ARealStationNeverOffersNoLimits) {
  const fs::path dir = FreshDir();
  std::ifstream in(kConfigs / "station-example-real.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::string toml = text.str();
  toml = toml.substr(0, toml.find("\n[offers]"));
  std::ofstream(dir / "station.toml") << toml << "\n[offers]\nno_limits = true\n";
  auto catalog = LoadPanelCatalog(dir / "station.toml");
  ASSERT_FALSE(catalog);
  EXPECT_NE(catalog.error().find("no_limits"), std::string::npos) << catalog.error();
  EXPECT_NE(catalog.error().find("production station"), std::string::npos) << catalog.error();
  fs::remove_all(dir);
}

TEST(PanelCatalog, SessionNamesAreDirectSubfoldersOnly) {
  const fs::path dir = FreshDir();
  fs::create_directories(dir / "SN1-20260101T000000Z");
  EXPECT_TRUE(IsSessionName(dir, "SN1-20260101T000000Z"));
  EXPECT_FALSE(IsSessionName(dir, "SN2"));  // does not exist
  EXPECT_FALSE(IsSessionName(dir, ".."));
  EXPECT_FALSE(IsSessionName(dir, "."));
  EXPECT_FALSE(IsSessionName(dir, "SN1-20260101T000000Z/.."));
  EXPECT_FALSE(IsSessionName(dir, ""));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hrgbench::app
