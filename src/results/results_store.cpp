// Opening (with migrations) and importing. The queries are in results_queries.cpp.

#include "hrgbench/results/results_store.hpp"

#include <filesystem>

#include "hrgbench/results/utc_text.hpp"
#include "results/schema.hpp"
#include "results/sql_connection.hpp"
#include "results/sql_values.hpp"

namespace hrgbench::results {
namespace {

using internal::Integer;
using internal::Real;
using internal::SqlConnection;
using internal::SqlValue;

// The version stored in the database; 0 for a database without the table (a new file).
std::expected<int, StoreError> StoredVersion(SqlConnection& db) {
  const char* exists_sql =
      db.engine() == Engine::kSqlite
          ? "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = 'schema_version'"
          : "SELECT count(*) FROM pg_catalog.pg_tables WHERE tablename = 'schema_version' AND "
            "schemaname = current_schema()";
  auto exists = db.Query(exists_sql);
  if (!exists) return std::unexpected(internal::ToStoreError(exists.error()));
  if (exists->empty() || internal::ToInteger((*exists)[0][0]) == 0) return 0;
  auto version = db.Query("SELECT max(version) FROM schema_version");
  if (!version) return std::unexpected(internal::ToStoreError(version.error()));
  if (version->empty()) return 0;
  return static_cast<int>(internal::ToInteger((*version)[0][0]));
}

StoreError Newer(const std::string& url, int stored) {
  return {StoreError::Kind::kSchemaMismatch,
          "results database '" + url + "' has schema version " + std::to_string(stored) +
              ", newer than this program's " + std::to_string(kSchemaVersion) +
              ": nothing written; upgrade hrg-bench/hrg-results to use it"};
}

StoreError BadUrl(std::string message) { return {StoreError::Kind::kBadUrl, std::move(message)}; }

// SQLite, version 1 → 2: every stored time as the canonical text (utc_text.hpp), so that text
// order is time order and both engines read back the same text. A time that is not one (a
// hand-edited row) stops the migration, naming the row: guessing would misplace the session.
std::expected<void, StoreError> CanonicalSqliteTimes(SqlConnection& db) {
  struct Column {
    const char* table;
    const char* key;
    const char* column;
  };
  for (const Column c :
       {Column{"session", "id", "started_utc"}, Column{"session", "id", "ended_utc"},
        Column{"unit", "serial", "first_seen_utc"}}) {
    auto rows = db.Query(std::string("SELECT ") + c.key + ", " + c.column + " FROM " + c.table);
    if (!rows) return std::unexpected(internal::ToStoreError(rows.error()));
    for (const internal::SqlRow& row : *rows) {
      const std::string text = internal::ToText(row[1]);
      if (text.empty()) continue;
      const auto canonical = CanonicalUtc(text);
      if (!canonical) {
        return std::unexpected(StoreError{StoreError::Kind::kFailed,
                                          std::string(c.table) + " " + internal::ToText(row[0]) +
                                              ": " + c.column + " '" + text +
                                              "' is not an ISO 8601 time with a zone"});
      }
      if (*canonical == text) continue;
      if (auto ok = db.Query(std::string("UPDATE ") + c.table + " SET " + c.column +
                                 " = $1 WHERE " + c.key + " = $2",
                             {*canonical, row[0]});
          !ok)
        return std::unexpected(internal::ToStoreError(ok.error()));
    }
  }
  return {};
}

}  // namespace

const char* ToString(StoreError::Kind kind) {
  switch (kind) {
    case StoreError::Kind::kBadUrl:
      return "bad URL";
    case StoreError::Kind::kUnavailable:
      return "unavailable";
    case StoreError::Kind::kSchemaMismatch:
      return "schema mismatch";
    case StoreError::Kind::kBusy:
      return "busy";
    case StoreError::Kind::kFailed:
      return "failed";
  }
  return "?";
}

const char* ToString(ImportStatus status) {
  switch (status) {
    case ImportStatus::kInserted:
      return "inserted";
    case ImportStatus::kReplaced:
      return "replaced";
    case ImportStatus::kUnchanged:
      return "unchanged";
  }
  return "?";
}

ResultsStore::ResultsStore(std::unique_ptr<internal::SqlConnection> connection, std::string url)
    : db_(std::move(connection)), url_(std::move(url)) {}
ResultsStore::~ResultsStore() = default;

Engine ResultsStore::engine() const { return db_->engine(); }

std::expected<std::unique_ptr<ResultsStore>, StoreError> ResultsStore::Open(
    std::string_view url, const OpenOptions& options) {
  auto parsed = ParseResultsUrl(url);
  if (!parsed) return std::unexpected(BadUrl(parsed.error()));
  return Open(*parsed, options);
}

std::expected<std::unique_ptr<ResultsStore>, StoreError> ResultsStore::OpenExisting(
    std::string_view url) {
  auto parsed = ParseResultsUrl(url);
  if (!parsed) return std::unexpected(BadUrl(parsed.error()));
  std::error_code ec;
  if (parsed->engine == Engine::kSqlite && !std::filesystem::exists(parsed->sqlite_path, ec) && !ec)
    return nullptr;
  OpenOptions read_only;
  read_only.migrate = false;
  read_only.create = false;
  return Open(*parsed, read_only);
}

std::expected<std::unique_ptr<ResultsStore>, StoreError> ResultsStore::Open(
    const ResultsUrl& url, const OpenOptions& options) {
  auto connection = url.engine == Engine::kSqlite
                        ? internal::OpenSqlite(url, options.sqlite_busy_timeout_ms, options.create)
                        : internal::OpenPostgres(url);
  if (!connection) return std::unexpected(internal::ToStoreError(connection.error()));
  std::unique_ptr<ResultsStore> store(new ResultsStore(std::move(*connection), url.text));
  if (auto ok = store->Migrate(options); !ok) return std::unexpected(ok.error());
  return store;
}

std::expected<void, StoreError> ResultsStore::Migrate(const OpenOptions& options) {
  // Read first, without a write lock: the common case (current schema) writes nothing, and a
  // newer schema is refused before anything is written.
  auto stored = StoredVersion(*db_);
  if (!stored) return std::unexpected(stored.error());
  found_version_ = *stored;
  if (*stored > kSchemaVersion) return std::unexpected(Newer(url_, *stored));
  if (*stored == kSchemaVersion) return {};
  if (!options.migrate) {
    // A reader never answers from an older schema: its columns would be missing or read wrong.
    return std::unexpected(StoreError{
        StoreError::Kind::kSchemaMismatch,
        *stored == 0
            ? "results database '" + url_ + "' holds no results store (no schema)"
            : "results database '" + url_ + "' has schema version " + std::to_string(*stored) +
                  ", older than this program's " + std::to_string(kSchemaVersion) +
                  ": nothing read; migrate it with `hrg-results --db URL migrate` (the "
                  "next upload of a session migrates it too)"});
  }
  if (auto begun = db_->BeginExclusive(); !begun)
    return std::unexpected(internal::ToStoreError(begun.error()));
  auto fail = [&](const StoreError& error) -> std::expected<void, StoreError> {
    (void)db_->Query("ROLLBACK");
    return std::unexpected(StoreError{
        error.kind, "results database '" + url_ + "': migration failed: " + error.message});
  };
  // Again under the lock: another station may have migrated meanwhile.
  auto locked = StoredVersion(*db_);
  if (!locked) return fail(locked.error());
  if (*locked > kSchemaVersion) {
    (void)db_->Query("ROLLBACK");
    return std::unexpected(Newer(url_, *locked));
  }
  if (*locked == 0) {
    if (auto ok = db_->Query("CREATE TABLE schema_version (version BIGINT PRIMARY KEY, "
                             "applied_utc TEXT NOT NULL)");
        !ok)
      return fail(internal::ToStoreError(ok.error()));
  }
  const auto& migrations = internal::Migrations();
  using Kind = internal::MigrationStep::Kind;
  const bool sqlite = db_->engine() == Engine::kSqlite;
  for (int version = *locked + 1; version <= kSchemaVersion; ++version) {
    for (const internal::MigrationStep& step : migrations[static_cast<std::size_t>(version - 1)]) {
      if ((step.kind == Kind::kSqliteOnly || step.kind == Kind::kSqliteTimes) && !sqlite) continue;
      if (step.kind == Kind::kPostgresOnly && sqlite) continue;
      if (step.kind == Kind::kSqliteTimes) {
        if (auto ok = CanonicalSqliteTimes(*db_); !ok) return fail(ok.error());
        continue;
      }
      if (step.kind == Kind::kFillFromFolders) {
        if (auto ok = FillFromFolders(); !ok) return fail(ok.error());
        continue;
      }
      if (auto ok = db_->Query(std::string(step.sql)); !ok)
        return fail(internal::ToStoreError(ok.error()));
    }
    const char* now_sql =
        db_->engine() == Engine::kSqlite
            ? "INSERT INTO schema_version VALUES ($1, strftime('%Y-%m-%dT%H:%M:%SZ','now'))"
            : "INSERT INTO schema_version VALUES ($1, to_char(now() AT TIME ZONE "
              "'UTC', 'YYYY-MM-DD\"T\"HH24:MI:SS\"Z\"'))";
    if (auto ok = db_->Query(now_sql, {Integer(version)}); !ok)
      return fail(internal::ToStoreError(ok.error()));
  }
  if (auto ok = db_->Query("COMMIT"); !ok) return fail(internal::ToStoreError(ok.error()));
  return {};
}

// Version 2's new session columns for the sessions version 1 stored: read again from each
// session's folder where it is still there (a line's sessions usually are); a folder that is gone
// or unreadable leaves them empty, as the record it came from would have (the hashes remain).
std::expected<void, StoreError> ResultsStore::FillFromFolders() {
  auto rows = db_->Query("SELECT id, path FROM session");
  if (!rows) return std::unexpected(internal::ToStoreError(rows.error()));
  for (const internal::SqlRow& row : *rows) {
    const std::string path = internal::ToText(row[1]);
    std::error_code ec;
    if (path.empty() ||
        !std::filesystem::is_regular_file(std::filesystem::path(path) / "session.json", ec))
      continue;
    auto record = ReadSessionRow(path);
    if (!record || record->id != internal::ToText(row[0])) continue;
    if (auto ok =
            db_->Query("UPDATE session SET sequence_name = $1, limits_name = $2, product = $3, "
                       "fixture_position = $4 WHERE id = $5",
                       {record->sequence_name, record->limits_name, record->product,
                        record->fixture_position, row[0]});
        !ok)
      return std::unexpected(internal::ToStoreError(ok.error()));
  }
  return {};
}

std::expected<std::optional<std::string>, StoreError> ResultsStore::StoredContentHash(
    const std::string& id) {
  auto rows = db_->Query("SELECT content_sha256 FROM session WHERE id = $1", {id});
  if (!rows) return std::unexpected(internal::ToStoreError(rows.error()));
  if (rows->empty()) return std::optional<std::string>();
  return std::optional<std::string>(internal::ToText((*rows)[0][0]));
}

std::expected<ImportStatus, StoreError> ResultsStore::Import(const SessionRow& record,
                                                             const ImportProbe& probe) {
  // A duplicate key means another writer stored the same session between our check and our
  // insert; the second attempt then sees it (unchanged, or replaces it).
  constexpr int kAttempts = 3;
  for (int attempt = 1;; ++attempt) {
    bool retry = false;
    auto status = ImportOnce(record, probe, &retry);
    if (status || !retry || attempt == kAttempts) return status;
  }
}

std::expected<ImportStatus, StoreError> ResultsStore::ImportOnce(const SessionRow& record,
                                                                 const ImportProbe& probe,
                                                                 bool* retry) {
  int statement = 0;
  auto run = [&](const std::string& sql,
                 const std::vector<SqlValue>& params) -> std::expected<void, internal::SqlError> {
    if (probe) probe(statement);
    ++statement;
    if (auto ok = db_->Query(sql, params); !ok) return std::unexpected(ok.error());
    return {};
  };
  auto fail = [&](const internal::SqlError& error) -> std::expected<ImportStatus, StoreError> {
    (void)db_->Query("ROLLBACK");  // a dead connection: the server rolled back already
    *retry = error.unique_violation;
    return std::unexpected(StoreError{error.kind, "session " + record.id + " (" + record.path +
                                                      "): not stored: " + error.message});
  };
  if (auto begun = db_->BeginWrite(); !begun) return fail(begun.error());
  auto stored = db_->Query("SELECT content_sha256 FROM session WHERE id = $1", {record.id});
  if (!stored) return fail(stored.error());
  ImportStatus status = ImportStatus::kInserted;
  if (!stored->empty()) {
    if (internal::ToText((*stored)[0][0]) == record.content_sha256) {
      (void)db_->Query("ROLLBACK");
      return ImportStatus::kUnchanged;
    }
    status = ImportStatus::kReplaced;
    for (const char* table : {"warning", "limit_verdict", "parameter", "run"}) {
      if (auto ok =
              run(std::string("DELETE FROM ") + table + " WHERE session_id = $1", {record.id});
          !ok)
        return fail(ok.error());
    }
    if (auto ok = run("DELETE FROM session WHERE id = $1", {record.id}); !ok)
      return fail(ok.error());
  }
  if (auto ok = run("INSERT INTO unit (serial, first_seen_utc) VALUES ($1, $2) ON CONFLICT "
                    "(serial) DO NOTHING",
                    {record.serial, record.started_utc});
      !ok)
    return fail(ok.error());
  // No end time: NULL in PostgreSQL (a timestamptz), "" in SQLite (whose column version 1 made
  // NOT NULL); both read back as "".
  const SqlValue ended = !record.ended_utc.empty() || db_->engine() == Engine::kSqlite
                             ? SqlValue(record.ended_utc)
                             : SqlValue();
  if (auto ok = run(
          "INSERT INTO session (id, serial, station, operator, software_version, "
          "station_sha256, sequence_sha256, limits_sha256, started_utc, ended_utc, "
          "outcome, reason, exit_code, complete_runs, path, content_sha256, sequence_name, "
          "limits_name, product, fixture_position) VALUES ($1, "
          "$2, $3, $4, $5, $6, $7, $8, $9, $10, $11, $12, $13, $14, $15, $16, $17, $18, $19, $20)",
          {record.id,
           record.serial,
           record.station,
           record.operator_name,
           record.software_version,
           record.station_sha256,
           record.sequence_sha256,
           record.limits_sha256,
           record.started_utc,
           ended,
           record.outcome,
           record.reason,
           Integer(record.exit_code),
           Integer(record.complete_runs),
           record.path,
           record.content_sha256,
           record.sequence_name,
           record.limits_name,
           record.product,
           record.fixture_position});
      !ok)
    return fail(ok.error());
  for (const RunRow& r : record.runs) {
    if (auto ok =
            run("INSERT INTO run VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11, $12, "
                "$13, $14)",
                {record.id, Integer(r.run_id), r.status, Real(r.commanded_omega_rad_s),
                 Real(r.free_run_s), Real(r.omega_rad_s), Real(r.omega_std_error_rad_s),
                 Real(r.earth_rate_rad_s), Real(r.temperature_start_c), Real(r.temperature_end_c),
                 Real(r.frequency_start_hz), Real(r.frequency_end_hz),
                 r.samples ? Integer(*r.samples) : SqlValue(), Integer(r.drops)});
        !ok)
      return fail(ok.error());
  }
  for (const ParameterRow& p : record.parameters) {
    if (auto ok = run("INSERT INTO parameter VALUES ($1, $2, $3, $4, $5)",
                      {record.id, p.name, Real(p.value), Real(p.std), p.unit});
        !ok)
      return fail(ok.error());
  }
  for (std::size_t i = 0; i < record.limits.size(); ++i) {
    const LimitRow& l = record.limits[i];
    if (auto ok = run("INSERT INTO limit_verdict VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9)",
                      {record.id, Integer(static_cast<std::int64_t>(i)), l.quantity, Real(l.min),
                       Real(l.max), Real(l.value), Real(l.std), l.status, l.message});
        !ok)
      return fail(ok.error());
  }
  for (std::size_t i = 0; i < record.warnings.size(); ++i) {
    if (auto ok = run("INSERT INTO warning VALUES ($1, $2, $3)",
                      {record.id, Integer(static_cast<std::int64_t>(i)), record.warnings[i]});
        !ok)
      return fail(ok.error());
  }
  if (probe) probe(statement);
  if (auto ok = db_->Query("COMMIT"); !ok) return fail(ok.error());
  return status;
}

}  // namespace hrgbench::results
