#include "results/schema.hpp"

namespace hrgbench::results::internal {

// Times are ISO 8601 UTC text ("2026-11-23T19:18:19.582862Z"), as session.json records them: they
// sort as text in both engines and need no time-zone handling. Children carry session_id with ON
// DELETE CASCADE, and the import deletes them explicitly too (SQLite enforces foreign keys only
// when the connection asks).
const std::vector<std::vector<std::string_view>>& Migrations() {
  static const std::vector<std::vector<std::string_view>> kAll = {
      // Version 1.
      {
          R"(CREATE TABLE unit (
               serial TEXT PRIMARY KEY,
               first_seen_utc TEXT))",
          R"(CREATE TABLE session (
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
               content_sha256 TEXT NOT NULL))",
          R"(CREATE TABLE run (
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
               PRIMARY KEY (session_id, run_id)))",
          R"(CREATE TABLE parameter (
               session_id TEXT NOT NULL REFERENCES session(id) ON DELETE CASCADE,
               name TEXT NOT NULL,
               value DOUBLE PRECISION,
               std DOUBLE PRECISION,
               unit TEXT NOT NULL,
               PRIMARY KEY (session_id, name)))",
          R"(CREATE TABLE limit_verdict (
               session_id TEXT NOT NULL REFERENCES session(id) ON DELETE CASCADE,
               seq BIGINT NOT NULL,
               quantity TEXT NOT NULL,
               min DOUBLE PRECISION,
               max DOUBLE PRECISION,
               value DOUBLE PRECISION,
               std DOUBLE PRECISION,
               status TEXT NOT NULL,
               message TEXT NOT NULL,
               PRIMARY KEY (session_id, seq)))",
          R"(CREATE TABLE warning (
               session_id TEXT NOT NULL REFERENCES session(id) ON DELETE CASCADE,
               seq BIGINT NOT NULL,
               text TEXT NOT NULL,
               PRIMARY KEY (session_id, seq)))",
          // history SERIAL; sessions --since/--station/--outcome; stats PARAM over a period.
          "CREATE INDEX session_serial_started ON session (serial, started_utc)",
          "CREATE INDEX session_started ON session (started_utc)",
          "CREATE INDEX session_station_started ON session (station, started_utc)",
          "CREATE INDEX session_outcome_started ON session (outcome, started_utc)",
          "CREATE INDEX parameter_name ON parameter (name, session_id)",
          "CREATE INDEX limit_verdict_quantity ON limit_verdict (quantity, session_id)",
      },
  };
  return kAll;
}

}  // namespace hrgbench::results::internal
