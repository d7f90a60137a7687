#include "results/schema.hpp"

namespace hrgbench::results::internal {

// Version 1 kept times as the ISO 8601 text session.json records. Version 2 (issue 26): PostgreSQL
// keeps them as timestamptz (a line's queries compare and truncate times without casts), SQLite as
// the canonical text "2026-11-23T19:18:19.582862Z" (always six fraction digits, so text order is
// time order), and both read back the same text (results_queries.cpp). Children carry session_id
// with ON DELETE CASCADE, and the import deletes them explicitly too (SQLite enforces foreign keys
// only when the connection asks).
using K = MigrationStep::Kind;

const std::vector<std::vector<MigrationStep>>& Migrations() {
  static const std::vector<std::vector<MigrationStep>> kAll = {
      // Version 1 (as released: never edit).
      {
          {K::kBoth, R"(CREATE TABLE unit (
               serial TEXT PRIMARY KEY,
               first_seen_utc TEXT))"},
          {K::kBoth, R"(CREATE TABLE session (
               id TEXT PRIMARY KEY,
               serial TEXT NOT NULL REFERENCES unit(serial),
               station TEXT NOT NULL,
               operator TEXT NOT NULL,
               software_version TEXT NOT NULL,
               station_sha256 TEXT NOT NULL,
               sequence_sha256 TEXT NOT NULL,
               limits_sha256 TEXT NOT NULL,
               started_utc TEXT NOT NULL,
               ended_utc TEXT NOT NULL,
               outcome TEXT NOT NULL,
               reason TEXT NOT NULL,
               exit_code BIGINT NOT NULL,
               complete_runs BIGINT NOT NULL,
               path TEXT NOT NULL,
               content_sha256 TEXT NOT NULL))"},
          {K::kBoth, R"(CREATE TABLE run (
               session_id TEXT NOT NULL REFERENCES session(id) ON DELETE CASCADE,
               run_id BIGINT NOT NULL,
               status TEXT NOT NULL,
               commanded_omega_rad_s DOUBLE PRECISION,
               free_run_s DOUBLE PRECISION,
               omega_rad_s DOUBLE PRECISION,
               omega_std_error_rad_s DOUBLE PRECISION,
               earth_rate_rad_s DOUBLE PRECISION,
               temperature_start_c DOUBLE PRECISION,
               temperature_end_c DOUBLE PRECISION,
               frequency_start_hz DOUBLE PRECISION,
               frequency_end_hz DOUBLE PRECISION,
               samples BIGINT,
               drops BIGINT NOT NULL,
               PRIMARY KEY (session_id, run_id)))"},
          {K::kBoth, R"(CREATE TABLE parameter (
               session_id TEXT NOT NULL REFERENCES session(id) ON DELETE CASCADE,
               name TEXT NOT NULL,
               value DOUBLE PRECISION,
               std DOUBLE PRECISION,
               unit TEXT NOT NULL,
               PRIMARY KEY (session_id, name)))"},
          {K::kBoth, R"(CREATE TABLE limit_verdict (
               session_id TEXT NOT NULL REFERENCES session(id) ON DELETE CASCADE,
               seq BIGINT NOT NULL,
               quantity TEXT NOT NULL,
               min DOUBLE PRECISION,
               max DOUBLE PRECISION,
               value DOUBLE PRECISION,
               std DOUBLE PRECISION,
               status TEXT NOT NULL,
               message TEXT NOT NULL,
               PRIMARY KEY (session_id, seq)))"},
          {K::kBoth, R"(CREATE TABLE warning (
               session_id TEXT NOT NULL REFERENCES session(id) ON DELETE CASCADE,
               seq BIGINT NOT NULL,
               text TEXT NOT NULL,
               PRIMARY KEY (session_id, seq)))"},
          // history SERIAL; sessions --since/--station/--outcome; stats PARAM over a period.
          {K::kBoth, "CREATE INDEX session_serial_started ON session (serial, started_utc)"},
          {K::kBoth, "CREATE INDEX session_started ON session (started_utc)"},
          {K::kBoth, "CREATE INDEX session_station_started ON session (station, started_utc)"},
          {K::kBoth, "CREATE INDEX session_outcome_started ON session (outcome, started_utc)"},
          {K::kBoth, "CREATE INDEX parameter_name ON parameter (name, session_id)"},
          {K::kBoth, "CREATE INDEX limit_verdict_quantity ON limit_verdict (quantity, session_id)"},
      },
      // Version 2 (issue 26): times as timestamptz (PostgreSQL) or canonical text (SQLite); the
      // sequence's and limits' names beside their hashes, the product, the fixture position; a
      // unit on every parameter row ("1" for a dimensionless one); each session's attempt.
      {
          {K::kPostgresOnly,
           "ALTER TABLE session ALTER COLUMN started_utc TYPE timestamptz USING "
           "started_utc::timestamptz"},
          {K::kPostgresOnly,
           "ALTER TABLE session ALTER COLUMN ended_utc TYPE timestamptz USING "
           "NULLIF(ended_utc, '')::timestamptz"},
          {K::kPostgresOnly, "ALTER TABLE session ALTER COLUMN ended_utc DROP NOT NULL"},
          {K::kPostgresOnly,
           "ALTER TABLE unit ALTER COLUMN first_seen_utc TYPE timestamptz USING "
           "NULLIF(first_seen_utc, '')::timestamptz"},
          {K::kSqliteTimes, ""},
          {K::kBoth, "ALTER TABLE session ADD COLUMN sequence_name TEXT NOT NULL DEFAULT ''"},
          {K::kBoth, "ALTER TABLE session ADD COLUMN limits_name TEXT NOT NULL DEFAULT ''"},
          {K::kBoth, "ALTER TABLE session ADD COLUMN product TEXT NOT NULL DEFAULT ''"},
          {K::kBoth, "ALTER TABLE session ADD COLUMN fixture_position TEXT NOT NULL DEFAULT ''"},
          // The units session_row.cpp now writes, for the rows version 1 left empty.
          {K::kBoth,
           "UPDATE parameter SET unit = '1/s' WHERE unit = '' AND name IN ('delta1', 'delta3', "
           "'delta4')"},
          {K::kBoth,
           "UPDATE parameter SET unit = 'rad/s' WHERE unit = '' AND name IN ('delta5', 'delta6')"},
          {K::kBoth,
           "UPDATE parameter SET unit = 'unit of y' WHERE unit = '' AND name = "
           "'residual_rms'"},
          {K::kBoth, "UPDATE parameter SET unit = '1' WHERE unit = ''"},
          {K::kFillFromFolders, ""},
          {K::kBoth,
           "CREATE INDEX session_sequence_started ON session (sequence_name, started_utc)"},
          // First pass or retest: a session's attempt is 1 + the unit's earlier sessions with the
          // same sequence (the same file, or the same name). Computed when read, so sessions
          // imported out of order (a sync of old folders) are still counted right.
          {K::kBoth,
           R"(CREATE VIEW session_attempt AS
               SELECT s.id AS session_id, 1 + (
                 SELECT count(*) FROM session e
                 WHERE e.serial = s.serial
                   AND (e.sequence_sha256 = s.sequence_sha256
                        OR (e.sequence_name <> '' AND e.sequence_name = s.sequence_name))
                   AND (e.started_utc < s.started_utc
                        OR (e.started_utc = s.started_utc AND e.id < s.id))) AS attempt
               FROM session s)"},
      },
  };
  return kAll;
}

}  // namespace hrgbench::results::internal
