#pragma once
// The one thing the two engines differ in: how a statement reaches the database. Everything else
// (schema, migrations, import, queries) is the same SQL, written once in results_store.cpp.
//
// Statements use $1, $2 ... placeholders (PostgreSQL's; the SQLite engine rewrites them to ?1,
// ?2). Parameters are always bound, never pasted into the text: a serial "'; DROP TABLE unit; --"
// is stored as that text. Values travel as text or NULL; the engines convert. One connection per
// object; not thread-safe (one per thread or per process).

#include <expected>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hrgbench/config/results_url.hpp"
#include "hrgbench/results/store_error.hpp"

namespace hrgbench::results::internal {

using SqlValue = std::optional<std::string>;  // nullopt = NULL
using SqlRow = std::vector<SqlValue>;

struct SqlError {
  std::string message;
  bool unique_violation = false;  // two writers inserted the same key: the caller may retry
  StoreError::Kind kind = StoreError::Kind::kFailed;  // what the engine's code says it was
};

inline StoreError ToStoreError(const SqlError& error) { return {error.kind, error.message}; }

class SqlConnection {
 public:
  virtual ~SqlConnection() = default;
  // Runs one statement; returns its rows (empty for statements without a result).
  virtual std::expected<std::vector<SqlRow>, SqlError> Query(
      const std::string& sql, const std::vector<SqlValue>& params = {}) = 0;
  // Starts a write transaction that excludes other writers of the schema (migrations): SQLite
  // BEGIN IMMEDIATE; PostgreSQL BEGIN + a transaction-scoped advisory lock.
  virtual std::expected<void, SqlError> BeginExclusive() = 0;
  // Starts a write transaction (SQLite BEGIN IMMEDIATE, so a second writer waits for the lock
  // instead of failing on upgrade; PostgreSQL BEGIN).
  virtual std::expected<void, SqlError> BeginWrite() = 0;
  virtual Engine engine() const = 0;
};

// Opens a connection. SQLite: creates the file's parent directory and the file (unless `create`
// is false: then a missing file is an error); waits up to `busy_timeout_ms` for another writer.
// PostgreSQL: PQconnectdb with the URL, connect_timeout 10 s unless the URL says otherwise. Errors
// name the URL (never a password: the URL has none).
std::expected<std::unique_ptr<SqlConnection>, SqlError> OpenSqlite(const ResultsUrl& url,
                                                                   int busy_timeout_ms,
                                                                   bool create = true);
std::expected<std::unique_ptr<SqlConnection>, SqlError> OpenPostgres(const ResultsUrl& url);

}  // namespace hrgbench::results::internal
