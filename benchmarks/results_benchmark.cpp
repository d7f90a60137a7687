// The results database's figures (docs/results-store.md): per engine, the import of 1 000
// session folders (the test fixture of tests/support/session_fixture.hpp with 6 runs: the rows of
// a production session but fewer limits), one station upload (open + import + mark, as hrg-bench
// does after every session), and `stats` over 100 000 generated sessions (rows written by SQL,
// then ParameterValues + ComputeParameterStats as hrg-results stats runs them). PostgreSQL is a
// throwaway local server (Unix socket, fsync off, as in the tests). Prints a Markdown table.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>

#include "hrgbench/results/parameter_stats.hpp"
#include "hrgbench/results/upload.hpp"
#include "postgres_server.hpp"
#include "results/sql_connection.hpp"
#include "session_fixture.hpp"

namespace {

using namespace hrgbench;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

constexpr int kFolders = 1000;
constexpr int kGenerated = 100000;

const char* kSqliteGenerate[] = {
    "INSERT INTO unit VALUES ('SN-GEN', '2026-01-01')",
    "WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n WHERE i < 100000) "
    "INSERT INTO session SELECT 'g' || i, 'SN-GEN', 'st-' || (i % 8), '', 'gen', '', '', '', "
    "printf('2026-%02d-%02dT08:00:00Z', 1 + i % 12, 1 + i % 28), '', 'PASS', '', 0, 6, '/gen', "
    "'h' FROM n",
    "INSERT INTO parameter SELECT id, 'delta1', -0.001 + (CAST(substr(id, 2) AS INTEGER) % 1000) "
    "* 1e-7, 1e-9, '' FROM session WHERE id LIKE 'g%'",
    "INSERT INTO limit_verdict SELECT session_id, 0, 'delta1', -0.0012, -0.0008, value, 1e-9, "
    "CASE WHEN value > -0.00091 THEN 'FAIL' ELSE 'PASS' END, '' FROM parameter WHERE "
    "session_id LIKE 'g%'",
};
const char* kPostgresGenerate[] = {
    "INSERT INTO unit VALUES ('SN-GEN', '2026-01-01')",
    "INSERT INTO session SELECT 'g' || i, 'SN-GEN', 'st-' || (i % 8), '', 'gen', '', '', '', "
    "'2026-' || lpad((1 + i % 12)::text, 2, '0') || '-' || lpad((1 + i % 28)::text, 2, '0') || "
    "'T08:00:00Z', '', 'PASS', '', 0, 6, '/gen', 'h' FROM generate_series(1, 100000) i",
    "INSERT INTO parameter SELECT id, 'delta1', -0.001 + (substr(id, 2)::int % 1000) * 1e-7, "
    "1e-9, '' FROM session WHERE id LIKE 'g%'",
    "INSERT INTO limit_verdict SELECT session_id, 0, 'delta1', -0.0012, -0.0008, value, 1e-9, "
    "CASE WHEN value > -0.00091 THEN 'FAIL' ELSE 'PASS' END, '' FROM parameter WHERE "
    "session_id LIKE 'g%'",
};

void Measure(const std::string& engine, const std::string& url, const std::vector<fs::path>& dirs,
             const fs::path& one) {
  auto store = results::ResultsStore::Open(url);
  if (!store) {
    std::printf("| %s | %s | | | |\n", engine.c_str(), store.error().message.c_str());
    return;
  }
  auto t0 = Clock::now();
  int failed = 0;
  for (const fs::path& dir : dirs) failed += results::UploadSession(**store, dir).uploaded ? 0 : 1;
  const double import_s = Since(t0);

  t0 = Clock::now();
  const results::UploadOutcome up = results::UploadSession(url, one);
  (void)results::MarkUpload(one, url, up);
  const double upload_s = Since(t0);

  auto parsed = results::ParseResultsUrl(url);
  auto raw = engine == "SQLite" ? results::internal::OpenSqlite(*parsed, 30000)
                                : results::internal::OpenPostgres(*parsed);
  if (!raw) return;
  (void)(*raw)->BeginWrite();
  for (const char* sql : engine == "SQLite" ? kSqliteGenerate : kPostgresGenerate) {
    if (auto ok = (*raw)->Query(sql); !ok) std::fprintf(stderr, "%s\n", ok.error().message.c_str());
  }
  (void)(*raw)->Query("COMMIT");
  (void)(*raw)->Query("ANALYZE");
  t0 = Clock::now();
  auto samples = (*store)->ParameterValues("delta1", {});
  const results::ParameterStats st = results::ComputeParameterStats("delta1", *samples);
  const double stats_s = Since(t0);
  std::printf(
      "| %s | %.2f s (%.0f sessions/s)%s | %.1f ms | %zu | %.2f s (yield %.3f, %zu weeks) |\n",
      engine.c_str(), import_s, kFolders / import_s, failed ? " FAILURES" : "", upload_s * 1e3,
      st.n, stats_s, st.yield.value_or(0.0), st.weeks.size());
}

}  // namespace

int main() {
  std::random_device rd;
  const fs::path root =
      fs::temp_directory_path() / ("hrgbench-results-bench-" + std::to_string(rd()));
  std::vector<fs::path> dirs;
  for (int i = 0; i < kFolders; ++i) {
    testing::FixtureSession f;
    f.serial = "SN-" + std::to_string(i % 100);
    f.station = "st-" + std::to_string(i % 8);
    f.started_ns = i;
    f.runs = 6;
    f.delta1 = -1e-3 + 1e-7 * (i % 100);
    dirs.push_back(root / "sessions" / ("s" + std::to_string(i)));
    testing::WriteFixtureSession(dirs.back(), f);
  }
  testing::FixtureSession one_f;
  one_f.serial = "SN-ONE";
  one_f.runs = 6;
  const fs::path one = root / "one";
  testing::WriteFixtureSession(one, one_f);

  std::printf(
      "| engine | import of %d session folders | one station upload (open, import, mark) "
      "| sessions in stats | stats delta1 over them |\n|---|---|---|---|---|\n",
      kFolders);
  Measure("SQLite", "sqlite://" + (root / "results.sqlite").string(), dirs, one);
  if (testing::PostgresServer::Installed()) {
    testing::PostgresServer server;
    if (server.Start() && server.CreateDatabase("results")) {
      fs::remove(one / "session.json");
      testing::WriteFixtureSession(one, one_f);
      Measure("PostgreSQL 15", server.Url("results"), dirs, one);
    } else {
      std::printf("| PostgreSQL | %s | | | |\n", server.error().c_str());
    }
  }
  std::error_code ec;
  fs::remove_all(root, ec);
  return 0;
}
