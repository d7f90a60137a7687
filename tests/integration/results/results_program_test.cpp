// hrg-bench and hrg-results as a station meets them: a session whose database cannot be written
// ends with its own outcome and the mark "not uploaded"; `hrg-results sync` uploads it later; the
// queries answer from what the bench recorded. Both engines: SQLite, and PostgreSQL with the server
// down during the session. The station is station-sim.toml (faster than real time) with the paper's
// sequence (5 runs of 10 s at 100 Hz).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>

#include "postgres_server.hpp"
#include "required_tool.hpp"
#include "session_fixture.hpp"

namespace {

namespace fs = std::filesystem;
using hrgbench::testing::FixtureSession;
using hrgbench::testing::PostgresServer;
using hrgbench::testing::WriteFixtureSession;

const std::string kBin = HRGBENCH_BIN_DIR;
const fs::path kConfigs = fs::path(HRGBENCH_SOURCE_DIR) / "bench_configs";

struct Output {
  int exit_code = -1;
  std::string out;
};

Output RunCommand(const std::string& command, const fs::path& log) {
  const int status = std::system((command + " > " + log.string() + " 2>&1").c_str());
  Output o;
  o.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  o.out = text.str();
  return o;
}

nlohmann::json ReadJson(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

class ResultsProgram : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device rd;
    dir_ = fs::temp_directory_path() / ("hrgbench-resprog-" + std::to_string(rd()));
    fs::create_directories(dir_ / "sessions");
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  // station-sim.toml with its [results] url replaced.
  fs::path Station(const std::string& url) {
    std::ifstream in(kConfigs / "station-sim.toml");
    std::stringstream text;
    text << in.rdbuf();
    std::string toml = text.str();
    const std::string shipped = "url = \"sqlite://../build/out/results.sqlite\"";
    const std::size_t at = toml.find(shipped);
    EXPECT_NE(at, std::string::npos);
    toml.replace(at, shipped.size(), "url = \"" + url + "\"");
    const fs::path path = dir_ / "station.toml";
    std::ofstream(path) << toml;
    return path;
  }
  Output Bench(const fs::path& station, const std::string& serial, const fs::path& session) {
    return RunCommand(kBin + "/hrg-bench run --station " + station.string() + " --sequence " +
                          (kConfigs / "sequence-paper.toml").string() + " --serial " + serial +
                          " -o " + session.string(),
                      dir_ / "bench.log");
  }
  Output Results(const std::string& args) {
    return RunCommand(kBin + "/hrg-results " + args, dir_ / "results.log");
  }
  fs::path dir_;
};

TEST_F(ResultsProgram, AnUnwritableDatabaseLeavesTheOutcomeAndSyncUploadsLater) {
  std::ofstream(dir_ / "a-file") << "not a directory";
  const std::string bad_url = "sqlite://" + (dir_ / "a-file" / "results.sqlite").string();
  const fs::path session = dir_ / "sessions" / "SN-RES-1";
  const Output bench = Bench(Station(bad_url), "SN-RES-1", session);
  const nlohmann::json doc = ReadJson(session / "session.json");
  // The session's own outcome decides the exit code, as without a database.
  EXPECT_EQ(bench.exit_code, doc["outcome"]["exit_code"].get<int>()) << bench.out;
  EXPECT_EQ(doc["outcome"]["kind"], "PASS") << bench.out;
  ASSERT_TRUE(doc.contains("results")) << bench.out;
  EXPECT_EQ(doc["results"]["uploaded"], false);
  EXPECT_NE(doc["results"]["reason"].get<std::string>().find("a-file"), std::string::npos)
      << doc["results"].dump();
  EXPECT_NE(bench.out.find("not uploaded"), std::string::npos) << bench.out;

  const std::string db = "--db sqlite://" + (dir_ / "line.sqlite").string();
  Output sync = Results(db + " sync --sessions-root " + (dir_ / "sessions").string());
  EXPECT_EQ(sync.exit_code, 0) << sync.out;
  EXPECT_NE(sync.out.find("sync: 1 uploaded, 0 already stored"), std::string::npos) << sync.out;
  EXPECT_EQ(ReadJson(session / "session.json")["results"]["uploaded"], true);
  sync = Results(db + " sync --sessions-root " + (dir_ / "sessions").string());
  EXPECT_NE(sync.out.find("sync: 0 uploaded, 1 already stored"), std::string::npos) << sync.out;

  // The queries answer with what the bench recorded.
  const Output history = Results(db + " history SN-RES-1 --json");
  ASSERT_EQ(history.exit_code, 0) << history.out;
  const nlohmann::json h = nlohmann::json::parse(history.out);
  ASSERT_EQ(h.size(), 1u);
  EXPECT_EQ(h[0]["outcome"], "PASS");
  EXPECT_EQ(h[0]["values"]["delta1"], doc["outcome"]["estimate"]["delta"][0]);
  const Output stats = Results(db + " stats delta2 --csv");
  EXPECT_EQ(stats.exit_code, 0) << stats.out;
  EXPECT_EQ(
      stats.out.rfind("period,n,mean,std,min,max,unit,limit_min,limit_max,judged,passed,yield,"
                      "first_pass_judged,first_pass_passed,first_pass_yield,capability,cp,cpk,cpu,"
                      "cpl\nall,1,",
                      0),
      0u)
      << stats.out;
  // The same as JSON, for a script: one session, no spread yet.
  const Output stats_json = Results(db + " stats delta2 --json");
  ASSERT_EQ(stats_json.exit_code, 0) << stats_json.out;
  const nlohmann::json sj = nlohmann::json::parse(stats_json.out);
  EXPECT_EQ(sj["name"], "delta2");
  EXPECT_EQ(sj["n"], 1);
  EXPECT_EQ(sj["mean"], doc["outcome"]["estimate"]["delta"][1]);
  EXPECT_EQ(sj["min"], sj["max"]);
  ASSERT_EQ(sj["weeks"].size(), 1u);
  EXPECT_EQ(sj["weeks"][0]["n"], 1);
  const Output exported = Results(db + " export");
  EXPECT_EQ(exported.exit_code, 0) << exported.out;
  EXPECT_NE(exported.out.find(",delta1,"), std::string::npos) << exported.out;
  EXPECT_NE(exported.out.find("\n" + h[0]["id"].get<std::string>() + ",SN-RES-1,sim-ci,"),
            std::string::npos)
      << exported.out;
}

std::string ReadText(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The page's data block (session_report.hpp's contract: one report-data script).
nlohmann::json ReportData(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"report-data\">";
  const std::size_t at = html.find(open);
  if (at == std::string::npos) return nullptr;
  const std::size_t from = at + open.size();
  return nlohmann::json::parse(html.substr(from, html.find("</script>", from) - from));
}

// The report lists the unit's earlier sessions from the station's store (issue 10): none for its
// first session, the first for its second, each with the quantities the store holds; hrg-report
// --results lists the later one for the first (a session never lists itself).
TEST_F(ResultsProgram, TheReportListsTheUnitsEarlierSessionsFromTheStore) {
  const std::string url = "sqlite://" + (dir_ / "station.sqlite").string();
  const fs::path station = Station(url);
  const fs::path first = dir_ / "sessions" / "first", second = dir_ / "sessions" / "second";
  ASSERT_EQ(Bench(station, "SN-HIST", first).exit_code, 0);
  ASSERT_EQ(Bench(Station(url), "SN-OTHER", dir_ / "sessions" / "other").exit_code, 0);
  const Output bench = Bench(station, "SN-HIST", second);
  ASSERT_EQ(bench.exit_code, 0) << bench.out;

  const std::string first_page = ReadText(first / "report" / "report.html");
  EXPECT_NE(first_page.find("<section id=\"unit-history\">"), std::string::npos);
  EXPECT_NE(first_page.find("this is the unit's first session there"), std::string::npos);

  const std::string page = ReadText(second / "report" / "report.html");
  EXPECT_NE(page.find("<section id=\"unit-history\">"), std::string::npos);
  const nlohmann::json data = ReportData(page);
  ASSERT_TRUE(data.is_object());
  const nlohmann::json& history = data["derived"]["unit_history"];
  EXPECT_EQ(history["store"], url);
  EXPECT_EQ(history["unavailable"], "");
  ASSERT_EQ(history["count"], 1) << history.dump();  // not SN-OTHER, not itself
  const nlohmann::json& earlier = history["sessions"][0];
  const nlohmann::json first_doc = ReadJson(first / "session.json");
  EXPECT_EQ(earlier["outcome"], first_doc["outcome"]["kind"]);
  EXPECT_EQ(earlier["started_utc"], first_doc["started"]["utc"]);
  EXPECT_EQ(fs::path(earlier["path"].get<std::string>()), fs::absolute(first));
  for (const nlohmann::json& q : first_doc["outcome"]["estimate"]["engineering"]["quantities"]) {
    if (q["name"] != "tau_s") continue;
    EXPECT_EQ(earlier["values"]["tau_s"], q["value"]);
    // On the page, a derived number pointing at that value.
    EXPECT_NE(page.find("data-derived=\"/derived/unit_history/sessions/0/values/tau_s\""),
              std::string::npos);
  }

  // Regenerated afterwards with the store: the first session now sees the second.
  const Output report =
      RunCommand(kBin + "/hrg-report --no-pdf --no-figures --results " + url + " " + first.string(),
                 dir_ / "report.log");
  ASSERT_EQ(report.exit_code, 0) << report.out;
  const nlohmann::json again = ReportData(ReadText(first / "report" / "report.html"));
  ASSERT_EQ(again["derived"]["unit_history"]["count"], 1);
  EXPECT_EQ(fs::path(again["derived"]["unit_history"]["sessions"][0]["path"].get<std::string>()),
            fs::absolute(second));

  // A store that cannot be read: the page says so, the report is still written.
  std::ofstream(dir_ / "corrupt.sqlite") << "not a database, but long enough to be read as one";
  const Output broken = RunCommand(kBin + "/hrg-report --no-pdf --no-figures --results sqlite://" +
                                       (dir_ / "corrupt.sqlite").string() + " " + first.string(),
                                   dir_ / "report.log");
  EXPECT_EQ(broken.exit_code, 0) << broken.out;
  EXPECT_NE(broken.out.find("earlier sessions are not available"), std::string::npos) << broken.out;
  EXPECT_NE(ReadText(first / "report" / "report.html").find(": not available ("),
            std::string::npos);
  // A store that does not exist yet is not created by a reader: no earlier sessions.
  const fs::path absent = dir_ / "no-such-dir" / "x.sqlite";
  const Output fresh = RunCommand(kBin + "/hrg-report --no-pdf --no-figures --results sqlite://" +
                                      absent.string() + " " + first.string(),
                                  dir_ / "report.log");
  EXPECT_EQ(fresh.exit_code, 0) << fresh.out;
  EXPECT_FALSE(fs::exists(absent.parent_path()));
  EXPECT_EQ(
      ReportData(ReadText(first / "report" / "report.html"))["derived"]["unit_history"]["count"],
      0);
}

TEST_F(ResultsProgram, PostgresqlDownDuringTheSessionThenSyncAfterRestart) {
  HRGBENCH_REQUIRE(PostgresServer::Installed(), "PostgreSQL 15 server binaries (postgresql-15)");
  PostgresServer server;
  ASSERT_TRUE(server.Start()) << server.error();
  ASSERT_TRUE(server.CreateDatabase("line"));
  server.Stop();
  const fs::path session = dir_ / "sessions" / "SN-RES-2";
  const Output bench = Bench(Station(server.Url("line")), "SN-RES-2", session);
  const nlohmann::json doc = ReadJson(session / "session.json");
  EXPECT_EQ(bench.exit_code, doc["outcome"]["exit_code"].get<int>()) << bench.out;
  EXPECT_EQ(doc["results"]["uploaded"], false) << bench.out;
  EXPECT_NE(doc["results"]["reason"].get<std::string>().find("cannot connect"), std::string::npos)
      << doc["results"].dump();

  const std::string db = "--db '" + server.Url("line") + "'";
  // A database that is down is the station's I/O failure (2), not a bad command (4): a line's
  // script retries the one and fixes the other.
  const Output down = Results(db + " sessions");
  EXPECT_EQ(down.exit_code, 2) << down.out;
  EXPECT_NE(down.out.find("cannot connect"), std::string::npos) << down.out;

  ASSERT_TRUE(server.Resume()) << server.error();
  const Output sync = Results(db + " sync --sessions-root " + (dir_ / "sessions").string());
  EXPECT_EQ(sync.exit_code, 0) << sync.out;
  EXPECT_NE(sync.out.find("sync: 1 uploaded"), std::string::npos) << sync.out;
  const Output sessions = Results(db + " sessions --csv --serial-like 'sn-res-%'");
  EXPECT_EQ(sessions.exit_code, 0) << sessions.out;
  EXPECT_NE(sessions.out.find(",SN-RES-2,sim-ci,"), std::string::npos) << sessions.out;
}

// --since is compared with started_utc as text: "yesterday" once gave 0 rows and exit 0. Anything
// but an ISO 8601 UTC time or a prefix of one is a usage error naming the value.
TEST_F(ResultsProgram, ASinceThatIsNotATimeIsRefused) {
  const std::string db = "--db sqlite://" + (dir_ / "r.sqlite").string();
  for (const std::string since : {"yesterday", "2026-1", "23.11.2026", "2026-11-23 14:05"}) {
    Output o = Results(db + " sessions --since '" + since + "'");
    EXPECT_EQ(o.exit_code, 4) << since << ": " << o.out;
    EXPECT_NE(o.out.find("'" + since + "' is not a UTC time"), std::string::npos) << o.out;
  }
  // A store to read (a reader creates none): one session after both times.
  FixtureSession f;
  f.started_utc = "2026-11-24T08:00:00Z";
  WriteFixtureSession(dir_ / "sessions" / "s1", f);
  ASSERT_EQ(Results(db + " import " + (dir_ / "sessions" / "s1").string()).exit_code, 0);
  EXPECT_EQ(Results(db + " sessions --since 2026-11-23").exit_code, 0);
  EXPECT_EQ(Results(db + " stats delta1 --since 2026-11-23T14:05:00Z").exit_code, 0);
}

TEST_F(ResultsProgram, BadDatabaseUrlsAreUsageErrors) {
  Output o = Results("--db 'postgresql://u:secret@localhost/x' sessions");
  EXPECT_EQ(o.exit_code, 4);
  EXPECT_EQ(o.out.find("secret"), std::string::npos) << o.out;
  o = Results("--db sqlit:///tmp/x sessions");
  EXPECT_EQ(o.exit_code, 4);
  EXPECT_NE(o.out.find("unknown scheme"), std::string::npos) << o.out;
}

std::size_t Lines(const std::string& text) {
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

// 17 sessions as a line engineer loaded them (issue 26): long reasons, one with line breaks. The
// text table has one line per session (it glued a row onto a long reason: 17 sessions, 16 rows),
// and SQLite and PostgreSQL answer byte for byte the same.
TEST_F(ResultsProgram, SeventeenSessionsAreSeventeenRowsAndBothEnginesAgree) {
  HRGBENCH_REQUIRE(PostgresServer::Installed(), "PostgreSQL 15 server binaries (postgresql-15)");
  PostgresServer server;
  ASSERT_TRUE(server.Start()) << server.error();
  ASSERT_TRUE(server.CreateDatabase("line"));
  std::string dirs;
  for (int i = 0; i < 17; ++i) {
    FixtureSession f;
    f.serial = "SN-" + std::to_string(100 + i % 5);
    f.started_utc = "2026-11-" + std::to_string(10 + i) + "T08:00:00." + std::to_string(i) + "Z";
    f.started_ns = i;
    f.delta1 = -1e-3 + 1e-5 * i;
    f.delta1_status = i % 4 == 3 ? "FAIL" : "PASS";
    f.outcome = f.delta1_status;
    f.reason = std::string(i % 2 == 0 ? 400 : 20, 'r') + (i == 5 ? "\nsecond line\n" : "") +
               " \u00b1 end " + std::to_string(i);
    const fs::path dir = dir_ / "sessions" / ("s" + std::to_string(i));
    WriteFixtureSession(dir, f);
    dirs += " " + dir.string();
  }
  const std::string sqlite = "--db sqlite://" + (dir_ / "line.sqlite").string();
  const std::string pg = "--db '" + server.Url("line") + "'";
  ASSERT_EQ(Results(sqlite + " import" + dirs).exit_code, 0);
  ASSERT_EQ(Results(pg + " import" + dirs).exit_code, 0);
  const Output table = Results(sqlite + " sessions");
  ASSERT_EQ(table.exit_code, 0) << table.out;
  EXPECT_EQ(Lines(table.out), 17u + 2u) << table.out;  // header, 17 sessions, the count
  EXPECT_NE(table.out.find("\u2026\n"), std::string::npos) << table.out;  // cut, with an ellipsis
  EXPECT_NE(table.out.find("17 session(s)\n"), std::string::npos);
  for (const std::string query :
       {"sessions", "sessions --csv", "sessions --json", "history SN-101", "stats delta1",
        "stats delta1 --csv", "stats delta1 --json", "stats tau_s --by sequence", "export"}) {
    const Output a = Results(sqlite + " " + query);
    const Output b = Results(pg + " " + query);
    EXPECT_EQ(a.exit_code, 0) << query << ": " << a.out;
    EXPECT_EQ(a.out, b.out) << query;
  }
  // The same counts as the engines' own clients give.
  const Output listed = Results(sqlite + " sessions --json");
  EXPECT_EQ(nlohmann::json::parse(listed.out).size(),
            std::stoul(server.Query("line", "SELECT count(*) FROM session")));
  EXPECT_EQ(server.Query("line", "SELECT count(*) FROM session WHERE outcome = 'FAIL'"), "4\n");
}

// `stats nonsense` printed n = 0 and exited 0. An unknown name is a usage error listing the known
// ones; a known one with no value in the filtered sessions is not a success either.
TEST_F(ResultsProgram, StatsRefusesAnUnknownParameterAndAnAnswerOfNothing) {
  const fs::path dir = dir_ / "sessions" / "s1";
  WriteFixtureSession(dir, FixtureSession{});
  const std::string db = "--db sqlite://" + (dir_ / "r.sqlite").string();
  ASSERT_EQ(Results(db + " import " + dir.string()).exit_code, 0);
  const Output unknown = Results(db + " stats nonsense");
  EXPECT_EQ(unknown.exit_code, 4) << unknown.out;
  EXPECT_NE(unknown.out.find("unknown parameter 'nonsense'; known: "), std::string::npos)
      << unknown.out;
  for (const char* name : {"delta1", "xi4", "tau_s", "frequency_split_mhz", "residual_rms"})
    EXPECT_NE(unknown.out.find(name), std::string::npos) << name << ": " << unknown.out;
  const Output none = Results(db + " stats delta1 --since 2030");
  EXPECT_EQ(none.exit_code, 1) << none.out;
  EXPECT_NE(none.out.find("no stored session matching the filters has a value of 'delta1'"),
            std::string::npos)
      << none.out;
  const Output some = Results(db + " stats delta1");
  EXPECT_EQ(some.exit_code, 0) << some.out;
  EXPECT_NE(some.out.find("delta1 [1/s]: n = 1"), std::string::npos) << some.out;
}

// A reader never creates a database: it names the path it looked for (relative paths from the
// working directory) and exits 4. A station file's relative URL is its folder's, wherever
// hrg-results runs (issue 26: run elsewhere, it reported 0 sessions and created an empty file).
TEST_F(ResultsProgram, AReaderNeverCreatesAStoreAndAStationsRelativeUrlIsItsFolders) {
  fs::create_directories(dir_ / "elsewhere");
  const std::string in_elsewhere = "cd " + (dir_ / "elsewhere").string() + " && ";
  for (const std::string reader : {"sessions", "stats delta1", "export", "history SN-0001"}) {
    const Output o =
        RunCommand(in_elsewhere + kBin + "/hrg-results --db sqlite://rel/r.sqlite " + reader,
                   dir_ / "results.log");
    EXPECT_EQ(o.exit_code, 4) << reader << ": " << o.out;
    EXPECT_NE(
        o.out.find("no results store at " + (dir_ / "elsewhere" / "rel" / "r.sqlite").string()),
        std::string::npos)
        << o.out;
  }
  EXPECT_FALSE(fs::exists(dir_ / "elsewhere" / "rel"));

  // The station file in its own folder, its store beside it.
  fs::create_directories(dir_ / "station");
  std::ifstream shipped(kConfigs / "station-sim.toml");
  std::stringstream text;
  text << shipped.rdbuf();
  std::string toml = text.str();
  const std::string url = "url = \"sqlite://../build/out/results.sqlite\"";
  toml.replace(toml.find(url), url.size(), "url = \"sqlite://store/results.sqlite\"");
  std::ofstream(dir_ / "station" / "station.toml") << toml;
  const fs::path session = dir_ / "sessions" / "s1";
  WriteFixtureSession(session, FixtureSession{});
  const std::string station = "--station " + (dir_ / "station" / "station.toml").string();
  const Output imported =
      RunCommand(in_elsewhere + kBin + "/hrg-results " + station + " import " + session.string(),
                 dir_ / "results.log");
  ASSERT_EQ(imported.exit_code, 0) << imported.out;
  EXPECT_TRUE(fs::exists(dir_ / "station" / "store" / "results.sqlite"));
  EXPECT_FALSE(fs::exists(dir_ / "elsewhere" / "store"));
  const Output listed = Results(station + " sessions --csv");  // from the test's own directory
  EXPECT_EQ(listed.exit_code, 0) << listed.out;
  EXPECT_EQ(Lines(listed.out), 2u) << listed.out;
}

// A store of main's schema (1): readers say how to migrate it and read nothing; `migrate` does
// it; then the store answers. Checked with sqlite3 as the line would.
TEST_F(ResultsProgram, MigrateBringsAVersion1StoreToTheCurrentSchema) {
  HRGBENCH_REQUIRE(std::system("which sqlite3 > /dev/null") == 0, "the sqlite3 command (sqlite3)");
  const fs::path file = dir_ / "old.sqlite";
  const fs::path dump =
      fs::path(HRGBENCH_SOURCE_DIR) / "tests/data/results/store-v1-main-0e1c2c4.sql";
  ASSERT_EQ(std::system(("sqlite3 " + file.string() + " < " + dump.string()).c_str()), 0);
  const std::string db = "--db sqlite://" + file.string();
  const Output refused = Results(db + " sessions");
  EXPECT_EQ(refused.exit_code, 4) << refused.out;
  EXPECT_NE(refused.out.find("schema version 1, older than this program's 2"), std::string::npos)
      << refused.out;
  EXPECT_NE(refused.out.find("migrate"), std::string::npos) << refused.out;
  const Output migrated = Results(db + " migrate");
  EXPECT_EQ(migrated.exit_code, 0) << migrated.out;
  EXPECT_NE(migrated.out.find("migrate: schema version 1 -> 2"), std::string::npos) << migrated.out;
  EXPECT_NE(Results(db + " migrate").out.find("schema version 2 already"), std::string::npos);
  const Output sessions = Results(db + " sessions --csv");
  EXPECT_EQ(sessions.exit_code, 0) << sessions.out;
  EXPECT_EQ(Lines(sessions.out), 4u) << sessions.out;
  EXPECT_NE(sessions.out.find(",1,true,2026-11-26T23:07:22.503225Z,"), std::string::npos)
      << sessions.out;
  EXPECT_NE(sessions.out.find(",2,false,2026-11-26T23:07:41.602747Z,"), std::string::npos)
      << sessions.out;
  const Output check = RunCommand("sqlite3 " + file.string() +
                                      " \"SELECT max(version) FROM schema_version; SELECT count(*) "
                                      "FROM parameter WHERE unit = ''\"",
                                  dir_ / "sqlite.log");
  EXPECT_EQ(check.out, "2\n0\n");
}

// stats per sequence with first-pass yield; the export with std, unit and the verdict's columns,
// each value the one sqlite3 reads from the store.
TEST_F(ResultsProgram, StatsPerSequenceAndAnExportWithStdUnitAndVerdicts) {
  std::ifstream in(kConfigs / "sequence-paper.toml");
  std::stringstream text;
  text << in.rdbuf();
  const std::string paper = text.str();
  std::string production = paper;
  production.replace(production.find("name = \"paper\""), 14, "name = \"prod\"");
  std::string dirs;
  for (int i = 0; i < 6; ++i) {
    FixtureSession f;
    f.serial = "SN-" + std::to_string(i / 2);  // each unit twice: a first pass and a retest
    f.started_utc = "2026-11-1" + std::to_string(i) + "T08:00:00Z";
    f.started_ns = i;
    f.sequence_toml = i < 4 ? production : paper;
    f.sequence_sha256 = i < 4 ? "prod" : "paper";
    f.delta1 = -1e-3 + 1e-5 * i;
    f.delta1_status = i == 0 ? "FAIL" : "PASS";
    const fs::path dir = dir_ / "sessions" / ("s" + std::to_string(i));
    WriteFixtureSession(dir, f);
    dirs += " " + dir.string();
  }
  const fs::path file = dir_ / "r.sqlite";
  const std::string db = "--db sqlite://" + file.string();
  ASSERT_EQ(Results(db + " import" + dirs).exit_code, 0);
  const Output by = Results(db + " stats delta1 --by sequence --json");
  ASSERT_EQ(by.exit_code, 0) << by.out;
  const nlohmann::json groups = nlohmann::json::parse(by.out);
  ASSERT_EQ(groups.size(), 2u) << by.out;
  EXPECT_EQ(groups[0]["group"]["sequence"], "paper");
  EXPECT_EQ(groups[0]["n"], 2);
  EXPECT_EQ(groups[1]["group"]["sequence"], "prod");
  EXPECT_EQ(groups[1]["n"], 4);
  // prod: SN-0 FAIL then PASS, SN-1 PASS, PASS: yield 3/4, first pass 1/2.
  EXPECT_EQ(groups[1]["judged"], 4);
  EXPECT_EQ(groups[1]["passed"], 3);
  EXPECT_EQ(groups[1]["first_pass_judged"], 2);
  EXPECT_EQ(groups[1]["first_pass_passed"], 1);
  EXPECT_EQ(groups[1]["capability"], "Cpk");
  EXPECT_EQ(groups[1]["unit"], "1/s");

  const Output exported = Results(db + " export");
  ASSERT_EQ(exported.exit_code, 0) << exported.out;
  std::istringstream lines(exported.out);
  std::string header, first;
  std::getline(lines, header);
  std::getline(lines, first);
  EXPECT_NE(header.find(",delta1,delta1_std,delta1_unit,delta1_limit_min,delta1_limit_max,"
                        "delta1_status,delta1_message,"),
            std::string::npos)
      << header;
  EXPECT_NE(header.find(",sequence,sequence_sha256,limits,limits_sha256,product,fixture_position,"
                        "attempt,first_pass,"),
            std::string::npos)
      << header;
  const Output stored = RunCommand(
      "sqlite3 " + file.string() +
          " \"SELECT p.value || ',' || p.std || ',' || p.unit || ',' || l.min || ',' || l.max || "
          "',' || l.status FROM parameter p JOIN limit_verdict l ON l.session_id = p.session_id "
          "AND l.quantity = p.name JOIN session s ON s.id = p.session_id WHERE p.name = 'delta1' "
          "ORDER BY s.started_utc LIMIT 1\"",
      dir_ / "sqlite.log");
  EXPECT_EQ(stored.out, "-0.001,1.0e-09,1/s,-0.0012,-0.0008,FAIL\n");
  EXPECT_NE(first.find(",-0.001,1e-09,1/s,-0.0012,-8e-04,FAIL,fixture,"), std::string::npos)
      << first;
}

}  // namespace
