// The line's questions as SQL: one statement each, filters bound as parameters.

#include <algorithm>

#include "hrgbench/results/results_store.hpp"
#include "hrgbench/results/since_utc.hpp"
#include "results/sql_connection.hpp"
#include "results/sql_values.hpp"

namespace hrgbench::results {
namespace {

using internal::SqlRow;
using internal::SqlValue;
using internal::ToText;

// A stored time as the canonical text (utc_text.hpp): SQLite holds that text already;
// PostgreSQL's timestamptz is formatted in UTC, so both engines give the same bytes.
std::string TimeText(Engine engine, const std::string& column, const std::string& alias) {
  if (engine == Engine::kSqlite) return column + " AS " + alias;
  return "to_char(" + column + " AT TIME ZONE 'UTC', 'YYYY-MM-DD\"T\"HH24:MI:SS.US\"Z\"') AS " +
         alias;
}

// The session columns ToSummary reads, on the session alias s joined with its attempt a.
std::string SessionColumns(Engine engine) {
  return "s.id, s.serial, s.station, s.operator, s.software_version, " +
         TimeText(engine, "s.started_utc", "started_utc") + ", " +
         TimeText(engine, "s.ended_utc", "ended_utc") +
         ", s.outcome, s.reason, s.path, s.content_sha256, s.exit_code, s.complete_runs, "
         "s.sequence_name, s.sequence_sha256, s.limits_name, s.limits_sha256, s.product, "
         "s.fixture_position, a.attempt";
}
constexpr std::size_t kSessionColumnCount = 20;
constexpr const char* kSessionFrom =
    " FROM session s JOIN session_attempt a ON a.session_id = s.id";

// " WHERE ..." for `filter` on the session alias s, appending its parameters to `params`.
std::string Where(const SessionFilter& filter, std::vector<SqlValue>& params,
                  std::string extra = "") {
  std::string where = std::move(extra);
  auto add = [&](const std::string& condition, const std::string& value) {
    params.push_back(value);
    where += (where.empty() ? "" : " AND ") + condition + "$" + std::to_string(params.size());
  };
  if (!filter.since_utc.empty()) add("s.started_utc >= ", SinceLowerBound(filter.since_utc));
  if (!filter.station.empty()) add("s.station = ", filter.station);
  if (!filter.outcome.empty()) add("s.outcome = ", filter.outcome);
  if (!filter.serial.empty()) add("s.serial = ", filter.serial);
  if (!filter.sequence.empty()) add("s.sequence_name = ", filter.sequence);
  if (!filter.limits.empty()) add("s.limits_name = ", filter.limits);
  if (!filter.product.empty()) add("s.product = ", filter.product);
  if (!filter.serial_like.empty()) {
    params.push_back(filter.serial_like);
    where += (where.empty() ? "" : " AND ") + std::string("lower(s.serial) LIKE lower($") +
             std::to_string(params.size()) + ")";
  }
  return where.empty() ? "" : " WHERE " + where;
}

SessionSummary ToSummary(const SqlRow& row) {
  SessionSummary s;
  s.id = ToText(row[0]);
  s.serial = ToText(row[1]);
  s.station = ToText(row[2]);
  s.operator_name = ToText(row[3]);
  s.software_version = ToText(row[4]);
  s.started_utc = ToText(row[5]);
  s.ended_utc = ToText(row[6]);
  s.outcome = ToText(row[7]);
  s.reason = ToText(row[8]);
  s.path = ToText(row[9]);
  s.content_sha256 = ToText(row[10]);
  s.exit_code = static_cast<int>(internal::ToInteger(row[11]));
  s.complete_runs = static_cast<int>(internal::ToInteger(row[12]));
  s.sequence_name = ToText(row[13]);
  s.sequence_sha256 = ToText(row[14]);
  s.limits_name = ToText(row[15]);
  s.limits_sha256 = ToText(row[16]);
  s.product = ToText(row[17]);
  s.fixture_position = ToText(row[18]);
  s.attempt = static_cast<int>(internal::ToInteger(row[19]));
  return s;
}

}  // namespace

std::expected<std::vector<SessionSummary>, StoreError> ResultsStore::Sessions(
    const SessionFilter& filter) {
  std::vector<SqlValue> params;
  const std::string selected =
      "SELECT " + SessionColumns(engine()) + kSessionFrom + Where(filter, params);
  // The newest N by the same order, turned back: both engines take a LIMIT in a subquery.
  const std::string sql =
      filter.newest == 0
          ? selected + " ORDER BY s.started_utc, s.id"
          : "SELECT * FROM (" + selected + " ORDER BY s.started_utc DESC, s.id DESC LIMIT " +
                std::to_string(filter.newest) + ") newest ORDER BY started_utc, id";
  auto rows = db_->Query(sql, params);
  if (!rows) return std::unexpected(internal::ToStoreError(rows.error()));
  std::vector<SessionSummary> out;
  out.reserve(rows->size());
  for (const SqlRow& row : *rows) out.push_back(ToSummary(row));
  return out;
}

std::expected<std::vector<ParameterSample>, StoreError> ResultsStore::ParameterValues(
    const std::string& name, const SessionFilter& filter) {
  std::vector<SqlValue> params{name};
  const std::string sql =
      "SELECT s.id, s.serial, s.station, " + TimeText(engine(), "s.started_utc", "started_utc") +
      ", p.value, p.std, p.unit, l.status, l.min, l.max, s.sequence_name, s.limits_name, "
      "s.product, a.attempt FROM parameter p JOIN session s ON s.id = p.session_id JOIN "
      "session_attempt a ON a.session_id = s.id LEFT JOIN limit_verdict l ON l.session_id = "
      "p.session_id AND l.quantity = p.name" +
      Where(filter, params, "p.name = $1 AND p.value IS NOT NULL") +
      " ORDER BY s.started_utc, s.id";
  auto rows = db_->Query(sql, params);
  if (!rows) return std::unexpected(internal::ToStoreError(rows.error()));
  std::vector<ParameterSample> out;
  out.reserve(rows->size());
  for (const SqlRow& row : *rows) {
    ParameterSample p;
    p.session_id = ToText(row[0]);
    p.serial = ToText(row[1]);
    p.station = ToText(row[2]);
    p.started_utc = ToText(row[3]);
    p.value = internal::ToReal(row[4]).value_or(0.0);
    p.std = internal::ToReal(row[5]);
    p.unit = ToText(row[6]);
    p.limit_status = ToText(row[7]);
    p.limit_min = internal::ToReal(row[8]);
    p.limit_max = internal::ToReal(row[9]);
    p.sequence_name = ToText(row[10]);
    p.limits_name = ToText(row[11]);
    p.product = ToText(row[12]);
    p.attempt = static_cast<int>(internal::ToInteger(row[13]));
    out.push_back(std::move(p));
  }
  return out;
}

std::expected<std::vector<SessionWithParameters>, StoreError> ResultsStore::SessionsWithParameters(
    const SessionFilter& filter) {
  std::vector<SqlValue> params;
  const std::string sql = "SELECT " + SessionColumns(engine()) + ", p.name, p.value" +
                          kSessionFrom + " LEFT JOIN parameter p ON p.session_id = s.id" +
                          Where(filter, params) + " ORDER BY s.started_utc, s.id";
  auto rows = db_->Query(sql, params);
  if (!rows) return std::unexpected(internal::ToStoreError(rows.error()));
  std::vector<SessionWithParameters> out;
  for (const SqlRow& row : *rows) {
    if (out.empty() || out.back().session.id != ToText(row[0])) out.push_back({ToSummary(row), {}});
    const auto value = internal::ToReal(row[kSessionColumnCount + 1]);
    if (row[kSessionColumnCount] && value) out.back().values[*row[kSessionColumnCount]] = *value;
  }
  return out;
}

std::expected<std::vector<SessionExport>, StoreError> ResultsStore::ExportRows(
    const SessionFilter& filter) {
  std::vector<SessionExport> out;
  {
    std::vector<SqlValue> params;
    const std::string sql = "SELECT " + SessionColumns(engine()) +
                            ", p.name, p.value, p.std, p.unit" + kSessionFrom +
                            " LEFT JOIN parameter p ON p.session_id = s.id" +
                            Where(filter, params) + " ORDER BY s.started_utc, s.id";
    auto rows = db_->Query(sql, params);
    if (!rows) return std::unexpected(internal::ToStoreError(rows.error()));
    for (const SqlRow& row : *rows) {
      if (out.empty() || out.back().session.id != ToText(row[0]))
        out.push_back({ToSummary(row), {}, {}});
      const std::size_t c = kSessionColumnCount;
      if (!row[c]) continue;
      out.back().parameters[*row[c]] = {*row[c], internal::ToReal(row[c + 1]),
                                        internal::ToReal(row[c + 2]), ToText(row[c + 3])};
    }
  }
  // The verdicts in a second pass over the same sessions: one join with both children would
  // repeat each parameter once per verdict.
  std::map<std::string, SessionExport*> by_id;
  for (SessionExport& e : out) by_id[e.session.id] = &e;
  std::vector<SqlValue> params;
  const std::string sql =
      "SELECT s.id, l.quantity, l.min, l.max, l.value, l.std, l.status, l.message FROM session s "
      "JOIN limit_verdict l ON l.session_id = s.id" +
      Where(filter, params) + " ORDER BY s.id, l.seq";
  auto rows = db_->Query(sql, params);
  if (!rows) return std::unexpected(internal::ToStoreError(rows.error()));
  for (const SqlRow& row : *rows) {
    const auto it = by_id.find(ToText(row[0]));
    if (it == by_id.end()) continue;
    LimitRow l{ToText(row[1]),
               internal::ToReal(row[2]),
               internal::ToReal(row[3]),
               internal::ToReal(row[4]),
               internal::ToReal(row[5]),
               ToText(row[6]),
               ToText(row[7])};
    it->second->limits.emplace(l.quantity, std::move(l));  // the first verdict on a quantity
  }
  return out;
}

std::expected<std::vector<SessionSummary>, StoreError> ResultsStore::LatestPerStation() {
  const std::string sql =
      "SELECT " + SessionColumns(engine()) + kSessionFrom +
      " WHERE NOT EXISTS (SELECT 1 FROM session e WHERE e.station = s.station AND (e.started_utc > "
      "s.started_utc OR (e.started_utc = s.started_utc AND e.id > s.id))) ORDER BY s.station";
  auto rows = db_->Query(sql);
  if (!rows) return std::unexpected(internal::ToStoreError(rows.error()));
  std::vector<SessionSummary> out;
  for (const SqlRow& row : *rows) out.push_back(ToSummary(row));
  std::ranges::sort(out, {}, &SessionSummary::station);  // byte order, as ParameterNames
  return out;
}

std::expected<std::vector<std::string>, StoreError> ResultsStore::ParameterNames() {
  auto rows = db_->Query("SELECT DISTINCT name FROM parameter ORDER BY name");
  if (!rows) return std::unexpected(internal::ToStoreError(rows.error()));
  std::vector<std::string> out;
  for (const SqlRow& row : *rows) out.push_back(ToText(row[0]));
  std::ranges::sort(out);  // byte order: the engines' collations differ
  return out;
}

std::expected<std::vector<std::string>, StoreError> ResultsStore::Warnings(
    const std::string& session_id) {
  auto rows =
      db_->Query("SELECT text FROM warning WHERE session_id = $1 ORDER BY seq", {session_id});
  if (!rows) return std::unexpected(internal::ToStoreError(rows.error()));
  std::vector<std::string> out;
  for (const SqlRow& row : *rows) out.push_back(ToText(row[0]));
  return out;
}

}  // namespace hrgbench::results
