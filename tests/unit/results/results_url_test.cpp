// What a station file's [results] url may say, and what a bad database looks like to the user.
#include "hrgbench/config/results_url.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "hrgbench/results/results_store.hpp"

namespace {

using namespace hrgbench::results;
namespace fs = std::filesystem;

TEST(ResultsUrl, SqliteAndPostgresqlAreParsed) {
  auto sqlite = ParseResultsUrl("sqlite:///var/hrg/results.sqlite");
  ASSERT_TRUE(sqlite.has_value());
  EXPECT_EQ(sqlite->engine, Engine::kSqlite);
  EXPECT_EQ(sqlite->sqlite_path, "/var/hrg/results.sqlite");
  auto relative = ParseResultsUrl("sqlite://build/out/results.sqlite");
  ASSERT_TRUE(relative.has_value());
  EXPECT_EQ(relative->sqlite_path, "build/out/results.sqlite");
  auto pg = ParseResultsUrl("postgresql://station@db.line/results?sslmode=verify-full");
  ASSERT_TRUE(pg.has_value());
  EXPECT_EQ(pg->engine, Engine::kPostgres);
  EXPECT_EQ(pg->conninfo, "postgresql://station@db.line/results?sslmode=verify-full");
}

TEST(ResultsUrl, APasswordIsRefusedWithoutBeingEchoed) {
  for (const char* url : {"postgresql://station:hunter2@db/results",
                          "postgres://db/results?sslmode=require&password=hunter2",
                          "postgresql://db/results?PASSWORD=hunter2"}) {
    auto parsed = ParseResultsUrl(url);
    ASSERT_FALSE(parsed.has_value()) << url;
    EXPECT_NE(parsed.error().find("password"), std::string::npos) << parsed.error();
    EXPECT_EQ(parsed.error().find("hunter2"), std::string::npos) << parsed.error();
  }
}

TEST(ResultsUrl, TyposAndEmptyPathsAreClearErrors) {
  auto typo = ParseResultsUrl("sqlit:///tmp/x.sqlite");
  ASSERT_FALSE(typo.has_value());
  EXPECT_NE(typo.error().find("unknown scheme"), std::string::npos) << typo.error();
  EXPECT_FALSE(ParseResultsUrl("sqlite://").has_value());
  EXPECT_FALSE(ParseResultsUrl("").has_value());
  EXPECT_FALSE(ParseResultsUrl(std::string(2000, 'x')).has_value());
}

// The kind is what a program's exit code is decided on (hrg-results: 4 for the first two, 2 for the
// third), so each has its case.
TEST(ResultsUrl, StoreErrorsSayWhetherTheUrlTheSchemaOrTheDatabaseIsAtFault) {
  auto typo = ResultsStore::Open("sqlit:///tmp/x");
  ASSERT_FALSE(typo.has_value());
  EXPECT_EQ(typo.error().kind, StoreError::Kind::kBadUrl) << typo.error();
  std::random_device rd;
  const fs::path dir = fs::temp_directory_path() / ("hrgbench-kind-" + std::to_string(rd()));
  OpenOptions no_create;
  no_create.create = false;
  auto missing = ResultsStore::Open("sqlite://" + (dir / "none.db").string(), no_create);
  ASSERT_FALSE(missing.has_value());
  EXPECT_EQ(missing.error().kind, StoreError::Kind::kUnavailable) << missing.error();
  EXPECT_TRUE(missing.error().Transient());
}

TEST(ResultsUrl, ACorruptSqliteFileIsNamedInTheError) {
  std::random_device rd;
  const fs::path file = fs::temp_directory_path() / ("hrgbench-corrupt-" + std::to_string(rd()));
  std::ofstream(file) << std::string(4096, 'x');
  auto store = ResultsStore::Open("sqlite://" + file.string());
  ASSERT_FALSE(store.has_value());
  EXPECT_NE(store.error().message.find(file.string()), std::string::npos) << store.error();
  EXPECT_NE(store.error().message.find("not a database"), std::string::npos) << store.error();
  // A file that is there but not a database: a retry will not help, nor is the URL wrong.
  EXPECT_EQ(store.error().kind, StoreError::Kind::kFailed);
  EXPECT_FALSE(store.error().Transient());
  fs::remove(file);
}

}  // namespace
