// What the panel offers: the sequence-* and limits-* files beside the station that load with it,
// in name order; a broken one is left out, not fatal; no sequence at all is an error. And the
// session names the page may ask a report of.
#include "app/panel/panel_catalog.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

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

TEST(PanelCatalog, OffersTheFilesBesideTheStationThatLoad) {
  const fs::path dir = FreshDir();
  fs::copy_file(kConfigs / "station-sim.toml", dir / "station.toml");
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
  fs::copy_file(kConfigs / "station-sim.toml", dir / "station.toml");
  auto catalog = LoadPanelCatalog(dir / "station.toml");
  ASSERT_FALSE(catalog);
  EXPECT_NE(catalog.error().find("station.toml"), std::string::npos) << catalog.error();
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
