#pragma once
// The results database: the index a production line works from. Session folders stay the complete
// raw record; the store holds per session its unit, station, operator, software version, config
// hashes and the sequence's and limits' names, product, fixture position, times, outcome and
// reason, folder path and content hash (session) and whether it was the unit's first pass with
// that sequence or a retest (session_attempt, computed when read), per run the plan,
// measured Ω and its standard error, Earth rate, temperature and frequency drift, samples, drops
// and status (run), the estimated δ, ξ and engineering quantities with their std and unit
// (parameter), the limit verdicts (limit_verdict) and the warnings (warning).
//
// One interface, two engines (results_url.hpp): SQLite (a file beside the sessions) and PostgreSQL
// (one server for a line). The SQL is the same for both; only the connection differs.
//
// Schema versions: the program carries migrations 1..kSchemaVersion and applies the missing ones
// when a writer opens a database (in one exclusive transaction, so two stations opening a new
// database at once do not race). A database whose version is newer than the program's is refused
// before anything is written ("upgrade hrg-bench/hrg-results"); a reader (OpenExisting) refuses an
// older one with a message saying how to migrate it, rather than answer from columns it lacks.
//
// Times: PostgreSQL keeps timestamptz, SQLite the canonical text of utc_text.hpp; every query
// returns that text, so both engines answer byte for byte the same.
//
// Import is one transaction and idempotent: the session's stable id (session_record.hpp) is the
// key; a session already stored with the same content hash is left as it is (kUnchanged); with a
// different hash (a resumed session, closed again) its rows are replaced (kReplaced). A failed
// import (server gone, disk full) leaves no partial rows: the transaction rolls back.
//
// Threads: one ResultsStore per thread. Several processes (stations) may write at once: SQLite
// queues writers (busy timeout 30 s), PostgreSQL runs them concurrently; a duplicate-key race on
// the same session is retried. Never throws (except std::bad_alloc); errors are StoreError values
// (store_error.hpp): a kind the caller decides on, a message naming the database and what failed.

#include <cstddef>
#include <cstdint>
#include <expected>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hrgbench/config/results_url.hpp"
#include "hrgbench/results/session_row.hpp"
#include "hrgbench/results/store_error.hpp"

namespace hrgbench::results {

namespace internal {
class SqlConnection;
}

// The schema this program writes and reads.
inline constexpr int kSchemaVersion = 2;

enum class ImportStatus { kInserted, kReplaced, kUnchanged };
const char* ToString(ImportStatus status);

// Filters shared by the queries; empty means "any".
struct SessionFilter {
  std::string since_utc;    // started_utc >= this (ISO 8601 prefix: "2026-11", "2026-11-23")
  std::string station;      // exact station name
  std::string outcome;      // PASS, FAIL, ERROR, ABORTED
  std::string serial_like;  // SQL LIKE pattern on the serial (% and _), case-insensitive
  std::string serial;       // exact serial
  std::string sequence;     // exact sequence name
  std::string limits;       // exact limits name
  std::string product;      // exact product
  // Sessions() only: at most this many, the newest (still returned oldest first); 0: all.
  std::size_t newest = 0;
};

struct SessionSummary {
  std::string id, serial, station, operator_name, software_version;
  std::string started_utc, ended_utc, outcome, reason, path, content_sha256;
  std::string sequence_name, sequence_sha256, limits_name, limits_sha256;  // "" when none
  std::string product, fixture_position;                                   // "" when none
  int exit_code = 0;
  int complete_runs = 0;
  int attempt = 1;  // 1: the unit's first pass with this sequence; 2, 3 ...: retests
};

// One parameter's value in one session, with the limit verdict of that session on it (if any).
struct ParameterSample {
  std::string session_id, serial, station, started_utc;
  std::string sequence_name, limits_name, product;
  int attempt = 1;  // as SessionSummary's
  double value = 0.0;
  std::optional<double> std;
  std::string unit;
  std::string limit_status;  // "" when the session had no limit on it
  std::optional<double> limit_min, limit_max;
};

// A session with every parameter it stored (name → value; undetermined ones absent).
struct SessionWithParameters {
  SessionSummary session;
  std::map<std::string, double> values;
};

// A session with its parameter rows and limit verdicts, by name (the export).
struct SessionExport {
  SessionSummary session;
  std::map<std::string, ParameterRow> parameters;
  std::map<std::string, LimitRow> limits;
};

struct OpenOptions {
  int sqlite_busy_timeout_ms = 30'000;  // a queued writer waits this long for the lock
  bool migrate = true;                  // false: refuse an older schema instead of migrating it
  bool create = true;  // false (SQLite): a missing file is an error, no file or directory made
};

// Test seam: called before each statement of an import with its 0-based index, so a test can stop
// the server in the middle of an upload. Empty in production.
using ImportProbe = std::function<void(int statement)>;

class ResultsStore {
 public:
  static std::expected<std::unique_ptr<ResultsStore>, StoreError> Open(
      const ResultsUrl& url, const OpenOptions& options = {});
  // Parses `url` first (results_url.hpp).
  static std::expected<std::unique_ptr<ResultsStore>, StoreError> Open(
      std::string_view url, const OpenOptions& options = {});
  // For readers that must write nothing (the panel's recent sessions, a report's unit history,
  // hrg-results' queries): no file, directory or schema is created or migrated; an older schema is
  // a kSchemaMismatch saying how to migrate it. nullptr when `url` names a SQLite file that does
  // not exist: nothing is stored (the caller says so, or answers empty).
  static std::expected<std::unique_ptr<ResultsStore>, StoreError> OpenExisting(
      std::string_view url);
  ~ResultsStore();
  ResultsStore(const ResultsStore&) = delete;
  ResultsStore& operator=(const ResultsStore&) = delete;

  Engine engine() const;
  const std::string& url() const { return url_; }

  // Writes `record` (see the contract above).
  std::expected<ImportStatus, StoreError> Import(const SessionRow& record,
                                                 const ImportProbe& probe = {});
  // The stored content hash of session `id`, nullopt when the session is not stored.
  std::expected<std::optional<std::string>, StoreError> StoredContentHash(const std::string& id);

  // Sessions matching `filter`, oldest first.
  std::expected<std::vector<SessionSummary>, StoreError> Sessions(const SessionFilter& filter);
  // Values of parameter `name` in the sessions matching `filter`, oldest first.
  std::expected<std::vector<ParameterSample>, StoreError> ParameterValues(
      const std::string& name, const SessionFilter& filter);
  // Sessions matching `filter` with all their parameters, oldest first (history, export).
  std::expected<std::vector<SessionWithParameters>, StoreError> SessionsWithParameters(
      const SessionFilter& filter);
  // The newest session of every station (the line view), by station name.
  std::expected<std::vector<SessionSummary>, StoreError> LatestPerStation();
  // Sessions matching `filter` with their parameter rows and verdicts, oldest first.
  std::expected<std::vector<SessionExport>, StoreError> ExportRows(const SessionFilter& filter);
  // Warnings of one session, in recorded order.
  std::expected<std::vector<std::string>, StoreError> Warnings(const std::string& session_id);
  // Every parameter name stored, sorted.
  std::expected<std::vector<std::string>, StoreError> ParameterNames();
  // The schema version this open found (before migrating); kSchemaVersion when it was current,
  // 0 for a new database.
  int found_version() const { return found_version_; }

 private:
  ResultsStore(std::unique_ptr<internal::SqlConnection> connection, std::string url);
  std::expected<void, StoreError> Migrate(const OpenOptions& options);
  std::expected<ImportStatus, StoreError> ImportOnce(const SessionRow& record,
                                                     const ImportProbe& probe, bool* retry);

  std::expected<void, StoreError> FillFromFolders();

  std::unique_ptr<internal::SqlConnection> db_;
  std::string url_;
  int found_version_ = kSchemaVersion;
};

}  // namespace hrgbench::results
