// hrg-bench and hrg-results as a station meets them: a session whose database cannot be written
// ends with its own outcome and the mark "not uploaded"; `hrg-results sync` uploads it later; the
// queries answer from what the bench recorded. Both engines: SQLite, and PostgreSQL with the server
// down during the session. The station is station-sim.toml (faster than real time) with the paper's
// sequence (5 runs of 10 s at 100 Hz).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>

#include "postgres_server.hpp"
#include "required_tool.hpp"

namespace {

namespace fs = std::filesystem;
using hrgbench::testing::PostgresServer;

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
    const std::string shipped = "url = \"sqlite://build/out/results.sqlite\"";
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
      stats.out.rfind("period,n,mean,std,min,max,limit_min,limit_max,yield,cp,cpk\nall,1,", 0), 0u)
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

}  // namespace
