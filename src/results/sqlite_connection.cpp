// The SQLite engine: the C API of Debian's libsqlite3. WAL journal, so readers (hrg-results)
// never block a station's upload; a busy timeout, so two writers queue instead of failing.

#include <sqlite3.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <thread>

#include "results/sql_connection.hpp"
#include "results/sql_values.hpp"

namespace hrgbench::results::internal {
namespace {

// $12 → ?12: SQLite's numbered parameters, same numbers.
std::string ToSqlitePlaceholders(const std::string& sql) {
  std::string out = sql;
  for (std::size_t i = 0; i + 1 < out.size(); ++i)
    if (out[i] == '$' && std::isdigit(static_cast<unsigned char>(out[i + 1]))) out[i] = '?';
  return out;
}

// SQLite's primary result code, as the store's callers decide on it.
StoreError::Kind KindOf(int code) {
  switch (code & 0xff) {
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
      return StoreError::Kind::kBusy;
    case SQLITE_CANTOPEN:
    case SQLITE_PERM:
    case SQLITE_AUTH:
      return StoreError::Kind::kUnavailable;
    default:
      return StoreError::Kind::kFailed;  // FULL, IOERR, CORRUPT, NOTADB, CONSTRAINT...
  }
}

class SqliteConnection final : public SqlConnection {
 public:
  SqliteConnection(sqlite3* db, std::string name) : db_(db), name_(std::move(name)) {}
  ~SqliteConnection() override { sqlite3_close_v2(db_); }
  SqliteConnection(const SqliteConnection&) = delete;
  SqliteConnection& operator=(const SqliteConnection&) = delete;

  std::expected<std::vector<SqlRow>, SqlError> Query(const std::string& sql,
                                                     const std::vector<SqlValue>& params) override {
    const std::string text = ToSqlitePlaceholders(sql);
    sqlite3_stmt* raw = nullptr;
    if (sqlite3_prepare_v2(db_, text.c_str(), static_cast<int>(text.size()), &raw, nullptr) !=
        SQLITE_OK) {
      return std::unexpected(Error());
    }
    std::unique_ptr<sqlite3_stmt, decltype(&sqlite3_finalize)> stmt(raw, sqlite3_finalize);
    for (std::size_t i = 0; i < params.size(); ++i) {
      const int index = static_cast<int>(i + 1);
      const int rc = params[i]
                         ? sqlite3_bind_text(stmt.get(), index, params[i]->data(),
                                             static_cast<int>(params[i]->size()), SQLITE_TRANSIENT)
                         : sqlite3_bind_null(stmt.get(), index);
      if (rc != SQLITE_OK) return std::unexpected(Error());
    }
    std::vector<SqlRow> rows;
    for (;;) {
      const int rc = sqlite3_step(stmt.get());
      if (rc == SQLITE_DONE) break;
      if (rc != SQLITE_ROW) return std::unexpected(Error());
      const int columns = sqlite3_column_count(stmt.get());
      SqlRow row(static_cast<std::size_t>(columns));
      for (int c = 0; c < columns; ++c) {
        const int type = sqlite3_column_type(stmt.get(), c);
        if (type == SQLITE_NULL) continue;
        if (type == SQLITE_FLOAT) {  // sqlite's own text has 15 digits: not round-trip
          row[static_cast<std::size_t>(c)] = Real(sqlite3_column_double(stmt.get(), c));
          continue;
        }
        const auto* bytes = reinterpret_cast<const char*>(sqlite3_column_text(stmt.get(), c));
        row[static_cast<std::size_t>(c)] =
            std::string(bytes, static_cast<std::size_t>(sqlite3_column_bytes(stmt.get(), c)));
      }
      rows.push_back(std::move(row));
    }
    return rows;
  }

  std::expected<void, SqlError> BeginExclusive() override { return BeginWrite(); }
  std::expected<void, SqlError> BeginWrite() override {
    if (auto ok = Query("BEGIN IMMEDIATE", {}); !ok) return std::unexpected(ok.error());
    return {};
  }
  Engine engine() const override { return Engine::kSqlite; }

 private:
  SqlError Error() const {
    const int code = sqlite3_extended_errcode(db_);
    return {"sqlite '" + name_ + "': " + sqlite3_errmsg(db_),
            code == SQLITE_CONSTRAINT_PRIMARYKEY || code == SQLITE_CONSTRAINT_UNIQUE, KindOf(code)};
  }
  sqlite3* db_;
  std::string name_;
};

}  // namespace

std::expected<std::unique_ptr<SqlConnection>, SqlError> OpenSqlite(const ResultsUrl& url,
                                                                   int busy_timeout_ms,
                                                                   bool create) {
  const std::filesystem::path file(url.sqlite_path);
  std::error_code ec;
  if (create && file.has_parent_path()) std::filesystem::create_directories(file.parent_path(), ec);
  sqlite3* db = nullptr;
  const int rc = sqlite3_open_v2(
      url.sqlite_path.c_str(), &db,
      SQLITE_OPEN_READWRITE | (create ? SQLITE_OPEN_CREATE : 0) | SQLITE_OPEN_FULLMUTEX, nullptr);
  if (rc != SQLITE_OK) {
    std::string message = "sqlite '" + url.sqlite_path +
                          "': cannot open: " + (db ? sqlite3_errmsg(db) : sqlite3_errstr(rc));
    if (ec) message += " (creating its directory: " + ec.message() + ")";
    sqlite3_close_v2(db);
    return std::unexpected(SqlError{std::move(message), false, StoreError::Kind::kUnavailable});
  }
  sqlite3_busy_timeout(db, busy_timeout_ms);
  sqlite3_extended_result_codes(db, 1);
  auto connection = std::make_unique<SqliteConnection>(db, url.sqlite_path);
  // The first statement reads the header: a file that is not a database fails here, by name.
  // Changing the journal mode takes the file's exclusive lock, and SQLite may answer SQLITE_BUSY
  // there without calling the busy handler (8 importers opening a new file at once: 1 open in
  // about 320 failed, issue 25 row 13). So a busy pragma is tried again, with a doubling pause
  // from 1 ms to 100 ms, for as long as the busy timeout allows any other statement to wait.
  for (const char* pragma :
       {"PRAGMA journal_mode=WAL", "PRAGMA foreign_keys=ON", "PRAGMA synchronous=NORMAL"}) {
    const auto start = std::chrono::steady_clock::now();
    const auto budget = std::chrono::milliseconds(std::max(busy_timeout_ms, 0));
    auto pause = std::chrono::milliseconds(1);
    for (;;) {
      auto ok = connection->Query(pragma, {});
      if (ok) break;
      const bool busy = ok.error().kind == StoreError::Kind::kBusy;
      if (!busy || std::chrono::steady_clock::now() - start + pause > budget) {
        ok.error().message += std::string(" (") + pragma + ")";
        return std::unexpected(ok.error());
      }
      std::this_thread::sleep_for(pause);
      pause = std::min(pause * 2, std::chrono::milliseconds(100));
    }
  }
  return connection;
}

}  // namespace hrgbench::results::internal
