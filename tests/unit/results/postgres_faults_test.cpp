// PostgreSQL faults a line meets: the server stopped in the middle of an upload, wrong
// credentials, and the station's role with only the rights an upload needs.
#include <gtest/gtest.h>

#include <random>

#include "hrgbench/results/results_store.hpp"
#include "hrgbench/results/upload.hpp"
#include "postgres_server.hpp"
#include "required_tool.hpp"
#include "session_fixture.hpp"

namespace {

using namespace hrgbench;
using hrgbench::testing::FixtureSession;
using hrgbench::testing::PostgresServer;
namespace fs = std::filesystem;

class PostgresFaults : public ::testing::Test {
 protected:
  void SetUp() override {
    HRGBENCH_REQUIRE(PostgresServer::Installed(), "PostgreSQL 15 server binaries (postgresql-15)");
    std::random_device rd;
    dir_ = fs::temp_directory_path() / ("hrgbench-pgfault-" + std::to_string(rd()));
    ASSERT_TRUE(server_.Start()) << server_.error();
    ASSERT_TRUE(server_.CreateDatabase("results"));
    url_ = server_.Url("results");
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path dir_;
  std::string url_;
  PostgresServer server_;
};

TEST_F(PostgresFaults, ServerStoppedMidUploadRollsBackAndSyncCompletesIt) {
  auto store = results::ResultsStore::Open(url_);
  ASSERT_TRUE(store.has_value()) << store.error();
  const fs::path session = dir_ / "s1";
  hrgbench::testing::WriteFixtureSession(session, FixtureSession{});
  // Stop the server after the session row and two of its runs went in, before the commit.
  bool stopped = false;
  const results::UploadOutcome outcome =
      results::UploadSession(**store, session, [&](int statement) {
        if (statement == 4 && !stopped) {
          server_.Stop();
          stopped = true;
        }
      });
  ASSERT_TRUE(stopped);
  EXPECT_FALSE(outcome.uploaded);
  EXPECT_NE(outcome.reason.find("not stored"), std::string::npos) << outcome.reason;
  ASSERT_TRUE(results::MarkUpload(session, url_, outcome).has_value());

  ASSERT_TRUE(server_.Resume()) << server_.error();
  auto reopened = results::ResultsStore::Open(url_);
  ASSERT_TRUE(reopened.has_value()) << reopened.error();
  // Rolled back: no session, no orphan runs.
  auto sessions = (*reopened)->Sessions({});
  ASSERT_TRUE(sessions.has_value());
  EXPECT_EQ(sessions->size(), 0u);
  auto values = (*reopened)->ParameterValues("delta1", {});
  ASSERT_TRUE(values.has_value());
  EXPECT_EQ(values->size(), 0u);
  // sync: the session is not stored, so it goes in now.
  const results::UploadOutcome again = results::UploadSession(**reopened, session);
  ASSERT_TRUE(again.uploaded) << again.reason;
  EXPECT_EQ(again.status, results::ImportStatus::kInserted);
  EXPECT_EQ((*reopened)->Sessions({})->size(), 1u);
}

TEST_F(PostgresFaults, WrongCredentialsAndAMissingDatabaseAreClearErrors) {
  ASSERT_TRUE(server_.Psql("postgres", "CREATE ROLE station LOGIN PASSWORD 'secret'"));
  // Trust authentication is for the postgres superuser only in this test: a role that must give a
  // password and has none (no .pgpass) is refused by the server.
  ASSERT_TRUE(server_.Psql("postgres", "ALTER SYSTEM SET password_encryption = 'scram-sha-256'"));
  auto missing = results::ResultsStore::Open(server_.Url("no_such_db"));
  ASSERT_FALSE(missing.has_value());
  EXPECT_NE(missing.error().message.find("no_such_db"), std::string::npos) << missing.error();
  EXPECT_NE(missing.error().message.find("cannot connect"), std::string::npos) << missing.error();
  // The server answers, but this database is not there: nothing a retry alone would change, yet
  // nothing the command's syntax got wrong either; the store reports what it met.
  EXPECT_EQ(missing.error().kind, results::StoreError::Kind::kUnavailable);
  auto nobody = results::ResultsStore::Open(server_.Url("results", "nobody"));
  ASSERT_FALSE(nobody.has_value());
  EXPECT_NE(nobody.error().message.find("nobody"), std::string::npos) << nobody.error();
  EXPECT_EQ(nobody.error().kind, results::StoreError::Kind::kUnavailable);
}

TEST_F(PostgresFaults, AStationRoleWithOnlyUploadRightsUploadsAndCannotAlterTheSchema) {
  {
    auto admin = results::ResultsStore::Open(url_);  // the administrator creates the schema
    ASSERT_TRUE(admin.has_value()) << admin.error();
  }
  // The role setup docs/results-store.md documents.
  ASSERT_TRUE(
      server_.Psql("results",
                   "CREATE ROLE station LOGIN; GRANT CONNECT ON DATABASE results TO station; "
                   "GRANT USAGE ON SCHEMA public TO station; "
                   "GRANT SELECT ON schema_version TO station; "
                   "GRANT SELECT, INSERT, DELETE ON unit, session, run, parameter, "
                   "limit_verdict, warning TO station"));
  const fs::path session = dir_ / "s1";
  hrgbench::testing::WriteFixtureSession(session, FixtureSession{});
  const results::UploadOutcome up =
      results::UploadSession(server_.Url("results", "station"), session);
  ASSERT_TRUE(up.uploaded) << up.reason;
  ASSERT_TRUE(server_.Psql("results", "DROP TABLE schema_version; DROP TABLE warning"));
  // A migration needs CREATE, which the station role lacks: refused, by name.
  auto migrate = results::ResultsStore::Open(server_.Url("results", "station"));
  ASSERT_FALSE(migrate.has_value());
  EXPECT_NE(migrate.error().message.find("migration failed"), std::string::npos) << migrate.error();
  EXPECT_EQ(migrate.error().kind, results::StoreError::Kind::kFailed);
}

}  // namespace
