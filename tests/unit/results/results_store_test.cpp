// The results database against both real engines: SQLite (a file in a temporary directory) and
// PostgreSQL (a server of Debian's postgresql-15 started per test process,
// support/postgres_server.hpp). Sessions are fixture folders with known values
// (support/session_fixture.hpp), so every expected answer below is derived by hand from the
// fixture's arguments. Designated initialisers name only the filters a test sets; the rest are
// empty on purpose.
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include "hrgbench/results/results_store.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include "hrgbench/config/sha256.hpp"
#include "hrgbench/results/parameter_stats.hpp"
#include "hrgbench/results/upload.hpp"
#include "hrgbench/results/utc_text.hpp"
#include "postgres_server.hpp"
#include "required_tool.hpp"
#include "session_fixture.hpp"

namespace {

using namespace hrgbench;
using hrgbench::testing::FixtureSession;
using hrgbench::testing::PostgresServer;
using hrgbench::testing::WriteFixtureSession;
namespace fs = std::filesystem;

class ResultsStoreTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    std::random_device rd;
    dir_ = fs::temp_directory_path() / ("hrgbench-results-" + std::to_string(rd()));
    fs::create_directories(dir_);
    if (GetParam() == "sqlite") {
      HRGBENCH_REQUIRE(std::system("which sqlite3 > /dev/null") == 0,
                       "the sqlite3 command (sqlite3)");
      url_ = "sqlite://" + (dir_ / "results.sqlite").string();
    } else {
      HRGBENCH_REQUIRE(PostgresServer::Installed(),
                       "PostgreSQL 15 server binaries (postgresql-15)");
      server_ = std::make_unique<PostgresServer>();
      ASSERT_TRUE(server_->Start()) << server_->error();
      ASSERT_TRUE(server_->CreateDatabase("results"));
      url_ = server_->Url("results");
    }
  }
  void TearDown() override {
    server_.reset();
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  std::unique_ptr<results::ResultsStore> Open() {
    auto store = results::ResultsStore::Open(url_);
    EXPECT_TRUE(store.has_value()) << store.error();
    return store ? std::move(*store) : nullptr;
  }
  fs::path Write(const std::string& name, const FixtureSession& f) {
    const fs::path dir = dir_ / "sessions" / name;
    WriteFixtureSession(dir, f);
    return dir;
  }
  // Runs one SQL statement outside the store (to set up what the program must refuse).
  bool RawSql(const std::string& sql) {
    if (GetParam() == "sqlite") {
      return std::system(
                 ("sqlite3 " + (dir_ / "results.sqlite").string() + " \"" + sql + "\"").c_str()) ==
             0;
    }
    return server_->Psql("results", sql);
  }

  // One query outside the store, as a line's engineer runs it (sqlite3 / psql): rows one a line,
  // columns separated by '|'.
  std::string RawQuery(const std::string& sql) {
    if (GetParam() == "postgres") return server_->Query("results", sql);
    const fs::path out = dir_ / "query.out";
    if (std::system(("sqlite3 " + (dir_ / "results.sqlite").string() + " \"" + sql + "\" > " +
                     out.string() + " 2>&1")
                        .c_str()) != 0)
      return "";
    std::ifstream in(out);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }
  // A store of schema version 1 as main's program wrote it (tests/data/results).
  bool LoadVersion1Store() {
    const fs::path dump =
        fs::path(HRGBENCH_SOURCE_DIR) / "tests/data/results/store-v1-main-0e1c2c4.sql";
    if (GetParam() == "postgres") return server_->PsqlFile("results", dump);
    return std::system(
               ("sqlite3 " + (dir_ / "results.sqlite").string() + " < " + dump.string()).c_str()) ==
           0;
  }

  fs::path dir_;
  std::string url_;
  std::unique_ptr<PostgresServer> server_;
};

std::string ReadText(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// PostgreSQL keeps times as timestamptz and SQLite as one canonical text; both answer with the
// same text, whatever zone or precision session.json wrote (issue 26: timestamps were text in
// PostgreSQL, and "…:00Z" sorted before "…:00.5Z" in SQLite).
TEST_P(ResultsStoreTest, TimesAreTimestamptzOrCanonicalTextAndReadBackTheSame) {
  auto store = Open();
  ASSERT_NE(store, nullptr);
  FixtureSession a;
  a.serial = "SN-A";
  a.started_utc = "2026-11-02T11:00:00.5+03:00";  // 08:00:00.5 UTC
  FixtureSession b;
  b.serial = "SN-B";
  b.started_utc = "2026-11-02T08:00:00Z";
  ASSERT_TRUE(results::UploadSession(*store, Write("a", a)).uploaded);
  ASSERT_TRUE(results::UploadSession(*store, Write("b", b)).uploaded);
  auto rows = store->Sessions({});
  ASSERT_TRUE(rows.has_value()) << rows.error();
  ASSERT_EQ(rows->size(), 2u);
  EXPECT_EQ(rows->at(0).serial, "SN-B");  // time order, not text order
  EXPECT_EQ(rows->at(0).started_utc, "2026-11-02T08:00:00.000000Z");
  EXPECT_EQ(rows->at(1).started_utc, "2026-11-02T08:00:00.500000Z");
  EXPECT_EQ(rows->at(1).ended_utc, "2026-11-02T08:00:00.500000Z");
  auto later = store->Sessions({.since_utc = "2026-11-02T08:00:00Z"});
  ASSERT_TRUE(later.has_value()) << later.error();
  EXPECT_EQ(later->size(), 2u);
  EXPECT_EQ(store->Sessions({.since_utc = "2026-11-02T08:00:01Z"})->size(), 0u);
  EXPECT_EQ(store->Sessions({.since_utc = "2026-11"})->size(), 2u);
  if (GetParam() == "postgres") {
    EXPECT_EQ(RawQuery("SELECT DISTINCT pg_typeof(started_utc) FROM session"),
              "timestamp with time zone\n");
    EXPECT_EQ(RawQuery("SELECT pg_typeof(first_seen_utc) FROM unit LIMIT 1"),
              "timestamp with time zone\n");
    // A line's query needs no cast.
    EXPECT_EQ(RawQuery("SELECT count(*) FROM session WHERE started_utc > "
                       "'2026-11-02 08:00:00.25+00'"),
              "1\n");
  } else {
    EXPECT_EQ(RawQuery("SELECT started_utc FROM session ORDER BY started_utc"),
              "2026-11-02T08:00:00.000000Z\n2026-11-02T08:00:00.500000Z\n");
  }
}

// Every parameter row has a unit ("1" when dimensionless); the sequence's and limits' names are
// beside their hashes, with the product, the fixture position and the operator; a unit's second
// session with the same sequence is a retest (issue 26).
TEST_P(ResultsStoreTest, UnitsNamesProductPositionOperatorAndRetests) {
  auto store = Open();
  ASSERT_NE(store, nullptr);
  const std::string paper =
      ReadText(fs::path(HRGBENCH_SOURCE_DIR) / "bench_configs" / "sequence-paper.toml");
  std::string other = paper;
  other.replace(other.find("name = \"paper\""), 14, "name = \"other\"");
  const std::string limits =
      "[limits]\nname = \"line-a\"\nproduct = \"HRG-30 grade A\"\ndelta1 = [-0.0012, "
      "-0.0008]\n";
  // SN-1: paper, paper (retest; an edited copy of the file, same name), other (first with it);
  // SN-2: paper.
  const struct {
    const char* serial;
    const std::string* sequence;
    const char* hash;
  } plan[] = {{"SN-1", &paper, "s1"},
              {"SN-1", &paper, "s2"},
              {"SN-1", &other, "s3"},
              {"SN-2", &paper, "s1"}};
  for (int i = 3; i >= 0; --i) {
    FixtureSession f;
    f.serial = plan[i].serial;
    f.started_utc = "2026-11-0" + std::to_string(2 + i) + "T08:00:00Z";
    f.started_ns = i;
    f.sequence_toml = *plan[i].sequence;
    f.sequence_sha256 = plan[i].hash;
    f.limits_toml = limits;
    f.fixture_position = i == 3 ? "C" : "";
    f.operator_name = "op-" + std::to_string(i);
    // Imported newest first: the attempt counts time, not import order.
    ASSERT_TRUE(results::UploadSession(*store, Write("s" + std::to_string(i), f)).uploaded);
  }
  auto rows = store->Sessions({});
  ASSERT_TRUE(rows.has_value()) << rows.error();
  ASSERT_EQ(rows->size(), 4u);
  const int attempts[] = {1, 2, 1, 1};
  for (int i = 0; i < 4; ++i) {
    const auto& s = rows->at(static_cast<std::size_t>(i));
    EXPECT_EQ(s.serial, plan[i].serial);
    EXPECT_EQ(s.sequence_name, i == 2 ? "other" : "paper");
    EXPECT_EQ(s.sequence_sha256, plan[i].hash);
    EXPECT_EQ(s.limits_name, "line-a");
    EXPECT_EQ(s.limits_sha256, "cc");
    EXPECT_EQ(s.product, "HRG-30 grade A");
    EXPECT_EQ(s.fixture_position, i == 3 ? "C" : "");
    EXPECT_EQ(s.operator_name, "op-" + std::to_string(i));
    EXPECT_EQ(s.attempt, attempts[i]) << i;
  }
  EXPECT_EQ(store->Sessions({.sequence = "other"})->size(), 1u);
  EXPECT_EQ(store->Sessions({.product = "HRG-30 grade A"})->size(), 4u);
  auto samples = store->ParameterValues("delta1", {});
  ASSERT_TRUE(samples.has_value());
  ASSERT_EQ(samples->size(), 4u);
  EXPECT_EQ(samples->at(1).attempt, 2);
  EXPECT_EQ(samples->at(1).unit, "1/s");
  // Checked as a line's engineer would, in the engine's own client.
  EXPECT_EQ(RawQuery("SELECT count(*) FROM parameter WHERE unit = ''"), "0\n");
  EXPECT_EQ(
      RawQuery("SELECT name || '=' || unit FROM parameter WHERE session_id = '" + rows->at(0).id +
               "' AND name IN ('delta1', 'delta2', 'delta5', 'xi1', 'residual_rms', "
               "'tau_s') ORDER BY name"),
      "delta1=1/s\ndelta2=1\ndelta5=rad/s\nresidual_rms=unit of y\ntau_s=s\nxi1=1\n");
  EXPECT_EQ(RawQuery("SELECT s.serial || '|' || s.sequence_name || '|' || a.attempt FROM session "
                     "s JOIN session_attempt a ON a.session_id = s.id ORDER BY s.started_utc"),
            "SN-1|paper|1\nSN-1|paper|2\nSN-1|other|1\nSN-2|paper|1\n");
  auto exported = store->ExportRows({});
  ASSERT_TRUE(exported.has_value()) << exported.error();
  ASSERT_EQ(exported->size(), 4u);
  const auto& first = exported->front();
  EXPECT_EQ(first.parameters.at("delta1").std, 1e-9);
  EXPECT_EQ(first.parameters.at("delta1").unit, "1/s");
  EXPECT_EQ(first.limits.at("delta1").status, "PASS");
  EXPECT_EQ(first.limits.at("delta1").min, -1.2e-3);
}

// A store made by main's program (schema 1): a reader refuses it, saying how to migrate, instead
// of answering from columns it lacks; the first writer migrates it; times, units and retests are
// then as a new store's (issue 26).
TEST_P(ResultsStoreTest, AVersion1StoreIsRefusedByReadersAndMigratedByTheFirstWriter) {
  ASSERT_TRUE(LoadVersion1Store());
  auto reader = results::ResultsStore::OpenExisting(url_);
  ASSERT_FALSE(reader.has_value());
  EXPECT_EQ(reader.error().kind, results::StoreError::Kind::kSchemaMismatch);
  EXPECT_NE(reader.error().message.find("schema version 1, older than this program's 2"),
            std::string::npos)
      << reader.error();
  EXPECT_NE(reader.error().message.find("hrg-results --db URL migrate"), std::string::npos)
      << reader.error();
  EXPECT_EQ(RawQuery("SELECT max(version) FROM schema_version"), "1\n");  // nothing written

  auto store = Open();
  ASSERT_NE(store, nullptr);
  EXPECT_EQ(store->found_version(), 1);
  EXPECT_EQ(RawQuery("SELECT max(version) FROM schema_version"), "2\n");
  auto rows = store->Sessions({});
  ASSERT_TRUE(rows.has_value()) << rows.error();
  ASSERT_EQ(rows->size(), 3u);
  EXPECT_EQ(rows->at(0).serial, "SN-V1-A");
  EXPECT_EQ(rows->at(0).started_utc, "2026-11-26T23:07:22.503225Z");
  EXPECT_EQ(rows->at(0).ended_utc, "2026-11-26T23:07:23.059023Z");
  EXPECT_EQ(rows->at(0).attempt, 1);
  EXPECT_EQ(rows->at(1).attempt, 2);  // the same unit and sequence again
  EXPECT_EQ(rows->at(2).attempt, 1);
  EXPECT_EQ(rows->at(2).limits_sha256, "");
  EXPECT_EQ(RawQuery("SELECT count(*) FROM parameter WHERE unit = ''"), "0\n");
  EXPECT_EQ(RawQuery("SELECT unit FROM parameter WHERE name = 'delta1' LIMIT 1"), "1/s\n");
  EXPECT_EQ(RawQuery("SELECT unit FROM parameter WHERE name = 'q_factor' LIMIT 1"), "1\n");
  if (GetParam() == "postgres") {
    EXPECT_EQ(RawQuery("SELECT DISTINCT pg_typeof(ended_utc) FROM session"),
              "timestamp with time zone\n");
  } else {
    EXPECT_EQ(RawQuery("SELECT first_seen_utc FROM unit ORDER BY serial"),
              "2026-11-26T23:07:22.503225Z\n2026-11-26T23:07:59.430723Z\n");
  }
  // A new session goes in beside the migrated ones, and the store reads as current.
  ASSERT_TRUE(results::UploadSession(*store, Write("new", FixtureSession{})).uploaded);
  auto again = results::ResultsStore::OpenExisting(url_);
  ASSERT_TRUE(again.has_value()) << again.error();
  EXPECT_EQ((*again)->Sessions({})->size(), 4u);
}

TEST_P(ResultsStoreTest, ImportTwiceChangesNothingAndRowsMatchTheFolder) {
  auto store = Open();
  ASSERT_NE(store, nullptr);
  FixtureSession f;
  f.operator_name = "A. Operator";
  const fs::path dir = Write("s1", f);
  auto first = results::UploadSession(*store, dir);
  ASSERT_TRUE(first.uploaded) << first.reason;
  EXPECT_EQ(first.status, results::ImportStatus::kInserted);
  auto second = results::UploadSession(*store, dir);
  ASSERT_TRUE(second.uploaded) << second.reason;
  EXPECT_EQ(second.status, results::ImportStatus::kUnchanged);

  auto sessions = store->Sessions({});
  ASSERT_TRUE(sessions.has_value()) << sessions.error();
  ASSERT_EQ(sessions->size(), 1u);
  const auto& s = sessions->front();
  EXPECT_EQ(s.serial, "SN-0001");
  EXPECT_EQ(s.station, "st-1");
  EXPECT_EQ(s.operator_name, "A. Operator");
  EXPECT_EQ(s.outcome, "PASS");
  EXPECT_EQ(s.complete_runs, 3);
  // The writer's form: the content hash is the file's SHA-256.
  EXPECT_EQ(s.content_sha256, *config_file::Sha256FileHex(dir / "session.json"));
  auto values = store->SessionsWithParameters({});
  ASSERT_TRUE(values.has_value());
  // Round-trip exact: the same doubles as in session.json.
  EXPECT_EQ(values->front().values.at("delta1"), -1e-3);
  EXPECT_EQ(values->front().values.at("tau_s"), 1000.0);
  EXPECT_EQ(values->front().values.count("frequency_axis_deg"), 0u);  // undetermined: no value
  auto warnings = store->Warnings(s.id);
  ASSERT_TRUE(warnings.has_value());
  EXPECT_EQ(*warnings, std::vector<std::string>{"fixture warning"});
}

// Readers (the panel, a report) open without writing: a SQLite file not there yet is nullptr and
// stays absent; an existing store answers as Open's does.
TEST_P(ResultsStoreTest, OpenExistingWritesNothing) {
  if (GetParam() == "sqlite") {
    const fs::path absent = dir_ / "not-yet" / "results.sqlite";
    auto none = results::ResultsStore::OpenExisting("sqlite://" + absent.string());
    ASSERT_TRUE(none.has_value()) << none.error();
    EXPECT_EQ(*none, nullptr);
    EXPECT_FALSE(fs::exists(absent.parent_path()));
  }
  auto store = Open();
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(results::UploadSession(*store, Write("s1", FixtureSession{})).uploaded);
  auto reader = results::ResultsStore::OpenExisting(url_);
  ASSERT_TRUE(reader.has_value()) << reader.error();
  ASSERT_NE(*reader, nullptr);
  auto rows = (*reader)->Sessions({});
  ASSERT_TRUE(rows.has_value()) << rows.error();
  EXPECT_EQ(rows->size(), 1u);
}

TEST_P(ResultsStoreTest, AResumedSessionReplacesItsRowsAndTheUploadMarkChangesNoHash) {
  auto store = Open();
  ASSERT_NE(store, nullptr);
  FixtureSession f;
  f.outcome = "ERROR";
  const fs::path dir = Write("s1", f);
  ASSERT_TRUE(results::UploadSession(*store, dir).uploaded);
  // The mark written after the upload leaves the content hash as it was.
  results::UploadOutcome marked{true, results::ImportStatus::kInserted, ""};
  ASSERT_TRUE(results::MarkUpload(dir, url_, marked).has_value());
  EXPECT_EQ(results::UploadSession(*store, dir).status, results::ImportStatus::kUnchanged);
  // Resumed and closed again: same start (same id), new outcome.
  f.outcome = "PASS";
  WriteFixtureSession(dir, f);
  auto replaced = results::UploadSession(*store, dir);
  ASSERT_TRUE(replaced.uploaded) << replaced.reason;
  EXPECT_EQ(replaced.status, results::ImportStatus::kReplaced);
  auto sessions = store->Sessions({});
  ASSERT_TRUE(sessions.has_value());
  ASSERT_EQ(sessions->size(), 1u);
  EXPECT_EQ(sessions->front().outcome, "PASS");
  auto values = store->ParameterValues("delta1", {});
  ASSERT_TRUE(values.has_value());
  EXPECT_EQ(values->size(), 1u);  // the old parameter rows are gone
}

// 12 sessions: serials SN-0000..SN-0003 (three each), stations st-a/st-b alternating, one per day
// from Monday 2026-11-02 (ISO weeks 45 and 46), every fourth one FAIL.
class Line {
 public:
  static FixtureSession Session(int i) {
    FixtureSession f;
    f.serial = "SN-000" + std::to_string(i % 4);
    f.station = i % 2 == 0 ? "st-a" : "st-b";
    char day[32];
    std::snprintf(day, sizeof day, "2026-11-%02dT08:00:00Z", 2 + i);
    f.started_utc = day;
    f.started_ns = i;
    f.delta1 = -1e-3 + 1e-5 * i;
    f.delta1_status = i % 4 == 3 ? "FAIL" : "PASS";
    f.outcome = f.delta1_status;
    f.tau_s = 1000.0 + i;
    return f;
  }
};

TEST_P(ResultsStoreTest, SessionsHistoryAndFiltersAnswerFromKnownSessions) {
  auto store = Open();
  ASSERT_NE(store, nullptr);
  for (int i = 0; i < 12; ++i) {
    auto up = results::UploadSession(*store, Write("s" + std::to_string(i), Line::Session(i)));
    ASSERT_TRUE(up.uploaded) << up.reason;
  }
  auto count = [&](const results::SessionFilter& filter) {
    auto rows = store->Sessions(filter);
    EXPECT_TRUE(rows.has_value());
    return rows ? rows->size() : 0u;
  };
  EXPECT_EQ(count({}), 12u);
  EXPECT_EQ(count({.since_utc = "2026-11-09"}), 5u);  // days 9..13: i = 7..11
  EXPECT_EQ(count({.station = "st-a"}), 6u);
  EXPECT_EQ(count({.outcome = "FAIL"}), 3u);          // i = 3, 7, 11
  EXPECT_EQ(count({.serial_like = "sn-000_"}), 12u);  // case-insensitive
  EXPECT_EQ(count({.serial_like = "%2"}), 3u);
  EXPECT_EQ(count({.station = "st-b", .outcome = "FAIL"}), 3u);
  // The panel's "last sessions of this station": the newest N, still oldest first.
  auto newest = store->Sessions({.station = "st-a", .newest = 2});
  ASSERT_TRUE(newest.has_value()) << newest.error();
  ASSERT_EQ(newest->size(), 2u);
  auto all_a = store->Sessions({.station = "st-a"});
  ASSERT_TRUE(all_a.has_value());
  EXPECT_EQ(newest->at(0).id, all_a->at(all_a->size() - 2).id);
  EXPECT_EQ(newest->at(1).id, all_a->back().id);
  EXPECT_LT(newest->at(0).started_utc, newest->at(1).started_utc);
  EXPECT_EQ(count({.newest = 50}), 12u);

  auto history = store->SessionsWithParameters({.serial = "SN-0001"});
  ASSERT_TRUE(history.has_value());
  ASSERT_EQ(history->size(), 3u);  // i = 1, 5, 9, oldest first
  for (std::size_t k = 0; k < 3; ++k) {
    const int i = 1 + 4 * static_cast<int>(k);
    EXPECT_EQ(history->at(k).values.at("tau_s"), 1000.0 + i);
    // The store's one text form of a time (utc_text.hpp).
    EXPECT_EQ(history->at(k).session.started_utc,
              *results::CanonicalUtc(Line::Session(i).started_utc));
  }
}

TEST_P(ResultsStoreTest, StatsGiveMeanStdYieldCpCpkAndTheWeeklyTrend) {
  auto store = Open();
  ASSERT_NE(store, nullptr);
  for (int i = 0; i < 12; ++i)
    ASSERT_TRUE(
        results::UploadSession(*store, Write("s" + std::to_string(i), Line::Session(i))).uploaded);
  auto samples = store->ParameterValues("delta1", {});
  ASSERT_TRUE(samples.has_value()) << samples.error();
  const results::ParameterStats st = results::ComputeParameterStats("delta1", *samples);
  // δ1 = -1e-3 + 1e-5 i, i = 0..11: mean -1e-3 + 5.5e-5; sample variance of 1e-5 i is
  // 1e-10 · n(n+1)/12 with n = 12 → 1e-10 · 13.
  const double mean = -1e-3 + 5.5e-5;
  const double std = 1e-5 * std::sqrt(13.0);
  EXPECT_EQ(st.n, 12u);
  EXPECT_NEAR(st.mean, mean, 1e-15);
  EXPECT_NEAR(st.std, std, 1e-15);
  EXPECT_DOUBLE_EQ(st.min, -1e-3);
  EXPECT_DOUBLE_EQ(st.max, -1e-3 + 1.1e-4);
  ASSERT_TRUE(st.yield.has_value());
  EXPECT_DOUBLE_EQ(*st.yield, 9.0 / 12.0);
  ASSERT_TRUE(st.cp && st.cpk);
  EXPECT_NEAR(*st.cp, 0.4e-3 / (6 * std), 1e-9);
  EXPECT_NEAR(*st.cpk, std::min(-0.8e-3 - mean, mean + 1.2e-3) / (3 * std), 1e-9);
  // Days 2..8 are ISO week 45 (i = 0..6), days 9..13 week 46 (i = 7..11).
  ASSERT_EQ(st.weeks.size(), 2u);
  EXPECT_EQ(st.weeks[0].week, "2026-W45");
  EXPECT_EQ(st.weeks[0].n, 7u);
  EXPECT_NEAR(st.weeks[0].mean, -1e-3 + 3e-5, 1e-15);
  EXPECT_EQ(st.weeks[1].week, "2026-W46");
  EXPECT_EQ(st.weeks[1].n, 5u);
  EXPECT_NEAR(st.weeks[1].mean, -1e-3 + 9e-5, 1e-15);
  // Filtered by station: the even i.
  auto a = store->ParameterValues("delta1", {.station = "st-a"});
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(a->size(), 6u);
}

TEST_P(ResultsStoreTest, SqlInSerialAndOperatorIsStoredAsText) {
  auto store = Open();
  ASSERT_NE(store, nullptr);
  FixtureSession f;
  f.serial = "SN'; DROP TABLE unit; --";
  f.operator_name = "Robert'); DROP TABLE session;--";
  ASSERT_TRUE(results::UploadSession(*store, Write("evil", f)).uploaded);
  auto rows = store->Sessions({.serial = f.serial});
  ASSERT_TRUE(rows.has_value()) << rows.error();
  ASSERT_EQ(rows->size(), 1u);
  EXPECT_EQ(rows->front().serial, f.serial);
  EXPECT_EQ(rows->front().operator_name, f.operator_name);
}

TEST_P(ResultsStoreTest, NonAsciiTextRoundTripsAndBytesThatAreNotUtf8AreRefusedByName) {
  auto store = Open();
  ASSERT_NE(store, nullptr);
  FixtureSession f;
  f.serial = "SN-\u00dcml\u00e4ut-\u65e5\u672c";  // UTF-8: Ü, ä, 日本
  f.operator_name = "J\u00f8rgen \u00c5str\u00f6m";
  ASSERT_TRUE(results::UploadSession(*store, Write("utf8", f)).uploaded);
  auto rows = store->Sessions({.serial = f.serial});
  ASSERT_TRUE(rows.has_value()) << rows.error();
  ASSERT_EQ(rows->size(), 1u);
  EXPECT_EQ(rows->front().serial, f.serial);
  EXPECT_EQ(rows->front().operator_name, f.operator_name);
  // session.json is JSON, which is UTF-8: a serial with a byte 0xFF is not a session (the reader
  // names the file); nothing is written.
  const fs::path bad = dir_ / "sessions" / "latin1";
  fs::create_directories(bad);
  std::string text = hrgbench::testing::FixtureDocument(FixtureSession{}).dump(2);
  text.replace(text.find("SN-0001"), 7, std::string("SN-") + char(0xff) + "01");
  std::ofstream(bad / "session.json") << text;
  const results::UploadOutcome refused = results::UploadSession(*store, bad);
  EXPECT_FALSE(refused.uploaded);
  EXPECT_NE(refused.reason.find((bad / "session.json").string()), std::string::npos)
      << refused.reason;
  EXPECT_EQ(store->Sessions({})->size(), 1u);
}

TEST_P(ResultsStoreTest, ANewerSchemaIsRefusedAndNothingWritten) {
  {
    auto store = Open();
    ASSERT_NE(store, nullptr);
  }
  ASSERT_TRUE(RawSql("INSERT INTO schema_version VALUES (99, 'future')"));
  auto refused = results::ResultsStore::Open(url_);
  ASSERT_FALSE(refused.has_value());
  EXPECT_NE(refused.error().message.find("schema version 99, newer than this program's 2"),
            std::string::npos)
      << refused.error();
  EXPECT_EQ(refused.error().kind, results::StoreError::Kind::kSchemaMismatch);
  EXPECT_FALSE(refused.error().Transient());
  const fs::path dir = Write("s1", FixtureSession{});
  auto upload = results::UploadSession(url_, dir);
  EXPECT_FALSE(upload.uploaded);
  EXPECT_NE(upload.reason.find("newer"), std::string::npos) << upload.reason;
  ASSERT_TRUE(RawSql("DELETE FROM schema_version WHERE version = 99"));
  auto store = Open();
  ASSERT_NE(store, nullptr);
  EXPECT_EQ(store->Sessions({})->size(), 0u);
}

TEST_P(ResultsStoreTest, ConcurrentUploadersLoseAndDoubleNothing) {
  // PostgreSQL: eight stations × 100 sessions at once. SQLite: the same in a smaller size (its
  // writers queue on one lock, which is what is checked).
  const bool pg = GetParam() == "postgres";
  const int stations = pg ? 8 : 4, per_station = pg ? 100 : 25;
  std::vector<fs::path> dirs;
  for (int s = 0; s < stations; ++s) {
    for (int k = 0; k < per_station; ++k) {
      FixtureSession f;
      f.serial = "SN-" + std::to_string(s) + "-" + std::to_string(k);
      f.station = "st-" + std::to_string(s);
      f.started_ns = s * 1000 + k;
      f.delta1 = -1e-3 + 1e-7 * (s * 1000 + k);
      dirs.push_back(Write(f.serial, f));
    }
  }
  { ASSERT_NE(Open(), nullptr); }  // schema first, as a line's administrator does
  std::atomic<int> failures{0};
  std::vector<std::thread> threads;
  for (int s = 0; s < stations; ++s) {
    threads.emplace_back([&, s] {
      auto store = results::ResultsStore::Open(url_);
      if (!store) {
        failures += per_station;
        return;
      }
      for (int k = 0; k < per_station; ++k) {
        auto up =
            results::UploadSession(**store, dirs[static_cast<std::size_t>(s * per_station + k)]);
        if (!up.uploaded) ++failures;
      }
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(failures.load(), 0);
  auto store = Open();
  ASSERT_NE(store, nullptr);
  auto rows = store->SessionsWithParameters({});
  ASSERT_TRUE(rows.has_value());
  ASSERT_EQ(rows->size(), dirs.size());
  std::set<std::string> ids;
  for (const auto& r : *rows) {
    ids.insert(r.session.id);
    auto record = results::ReadSessionRow(r.session.path);
    ASSERT_TRUE(record.has_value());
    EXPECT_EQ(record->content_sha256, r.session.content_sha256);
    EXPECT_EQ(r.values.at("delta1"), record->parameters.front().value.value());
  }
  EXPECT_EQ(ids.size(), dirs.size());
}

INSTANTIATE_TEST_SUITE_P(Engines, ResultsStoreTest, ::testing::Values("sqlite", "postgres"),
                         [](const ::testing::TestParamInfo<std::string>& engine) {
                           return engine.param;
                         });

}  // namespace
