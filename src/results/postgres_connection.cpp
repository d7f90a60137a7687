// The PostgreSQL engine: libpq (Debian's libpq5). Text parameters through PQexecParams only; the
// server converts them to the columns' types. The password comes from libpq itself (~/.pgpass,
// PGPASSFILE, a service file, PGPASSWORD): the URL has none (results_url.cpp refuses it).

#include <libpq-fe.h>

#include <cstring>
#include <string_view>

#include "results/sql_connection.hpp"

namespace hrgbench::results::internal {
namespace {

// 23505 unique_violation; 40001 serialization_failure; 40P01 deadlock: worth one retry.
bool Retryable(const char* sqlstate) {
  return sqlstate != nullptr &&
         (std::strcmp(sqlstate, "23505") == 0 || std::strcmp(sqlstate, "40001") == 0 ||
          std::strcmp(sqlstate, "40P01") == 0);
}

// Class 08 connection exception, 57P0x the server shutting down, 53xxx out of resources: the
// same request may work later. 55P03 lock_not_available: another writer holds it.
StoreError::Kind KindOf(const char* sqlstate, bool connection_bad) {
  if (connection_bad) return StoreError::Kind::kUnavailable;
  if (sqlstate == nullptr) return StoreError::Kind::kFailed;
  const std::string_view state(sqlstate);
  if (state.starts_with("08") || state.starts_with("57P0") || state.starts_with("53"))
    return StoreError::Kind::kUnavailable;
  if (state == "55P03") return StoreError::Kind::kBusy;
  return StoreError::Kind::kFailed;
}

class PostgresConnection final : public SqlConnection {
 public:
  PostgresConnection(PGconn* conn, std::string name) : conn_(conn), name_(std::move(name)) {}
  ~PostgresConnection() override { PQfinish(conn_); }
  PostgresConnection(const PostgresConnection&) = delete;
  PostgresConnection& operator=(const PostgresConnection&) = delete;

  std::expected<std::vector<SqlRow>, SqlError> Query(const std::string& sql,
                                                     const std::vector<SqlValue>& params) override {
    std::vector<const char*> values;
    values.reserve(params.size());
    for (const SqlValue& p : params) values.push_back(p ? p->c_str() : nullptr);
    std::unique_ptr<PGresult, decltype(&PQclear)> result(
        PQexecParams(conn_, sql.c_str(), static_cast<int>(params.size()), nullptr, values.data(),
                     nullptr, nullptr, 0),
        PQclear);
    const ExecStatusType status = result ? PQresultStatus(result.get()) : PGRES_FATAL_ERROR;
    if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK) {
      const char* sqlstate = result ? PQresultErrorField(result.get(), PG_DIAG_SQLSTATE) : nullptr;
      std::string message = result ? PQresultErrorMessage(result.get()) : PQerrorMessage(conn_);
      while (!message.empty() && (message.back() == '\n' || message.back() == ' '))
        message.pop_back();
      if (message.empty()) message = PQerrorMessage(conn_);
      return std::unexpected(SqlError{"postgresql '" + name_ + "': " + message, Retryable(sqlstate),
                                      KindOf(sqlstate, PQstatus(conn_) == CONNECTION_BAD)});
    }
    std::vector<SqlRow> rows;
    const int n = PQntuples(result.get());
    const int columns = PQnfields(result.get());
    rows.reserve(static_cast<std::size_t>(n));
    for (int r = 0; r < n; ++r) {
      SqlRow row(static_cast<std::size_t>(columns));
      for (int c = 0; c < columns; ++c) {
        if (PQgetisnull(result.get(), r, c)) continue;
        row[static_cast<std::size_t>(c)] =
            std::string(PQgetvalue(result.get(), r, c),
                        static_cast<std::size_t>(PQgetlength(result.get(), r, c)));
      }
      rows.push_back(std::move(row));
    }
    return rows;
  }

  std::expected<void, SqlError> BeginExclusive() override {
    if (auto ok = BeginWrite(); !ok) return ok;
    // Every program that migrates takes this lock first, so two stations opening a new database
    // at once do not both create the tables.
    if (auto ok = Query("SELECT pg_advisory_xact_lock(7202610)", {}); !ok)
      return std::unexpected(ok.error());
    return {};
  }
  std::expected<void, SqlError> BeginWrite() override {
    if (auto ok = Query("BEGIN", {}); !ok) return std::unexpected(ok.error());
    return {};
  }
  Engine engine() const override { return Engine::kPostgres; }

 private:
  PGconn* conn_;
  std::string name_;
};

}  // namespace

std::expected<std::unique_ptr<SqlConnection>, SqlError> OpenPostgres(const ResultsUrl& url) {
  // connect_timeout: a server that is down must not hold a station's session end for minutes.
  std::string conninfo = url.conninfo;
  if (conninfo.find("connect_timeout=") == std::string::npos)
    conninfo +=
        (conninfo.find('?') == std::string::npos ? "?" : "&") + std::string("connect_timeout=10");
  PGconn* conn = PQconnectdb(conninfo.c_str());
  if (conn == nullptr)
    return std::unexpected(
        SqlError{"postgresql '" + url.text + "': out of memory", false, StoreError::Kind::kFailed});
  if (PQstatus(conn) != CONNECTION_OK) {
    std::string message = PQerrorMessage(conn);
    while (!message.empty() && (message.back() == '\n' || message.back() == ' '))
      message.pop_back();
    PQfinish(conn);
    return std::unexpected(SqlError{"postgresql '" + url.text + "': cannot connect: " + message,
                                    false, StoreError::Kind::kUnavailable});
  }
  // Quiet NOTICEs ("relation already exists, skipping") that libpq prints on stderr.
  PQsetNoticeProcessor(
      conn, [](void*, const char*) {}, nullptr);
  return std::make_unique<PostgresConnection>(conn, url.text);
}

}  // namespace hrgbench::results::internal
