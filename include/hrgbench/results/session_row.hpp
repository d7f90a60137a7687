#pragma once
// One closed session as the results database holds it: the rows taken from the typed session
// record (session/session_record.hpp, the one reader of session.json); the folder stays the
// complete raw record, these rows are the index a line works from.
//
// Identity: `id` is stable for the life of a session: the first 32 hex digits of the SHA-256 of
// "serial \n station \n started.utc \n started.monotonic_ns", which a resume keeps, so a resumed
// session replaces its earlier rows instead of adding a second session.
// Content: `content_sha256` is the SHA-256 of session.json as the bench closed it: the text of the
// document without its "results" key (the upload mark, written after the upload) in the writer's
// form (sorted keys, 2-space indent, final newline). For a file that carries no mark this is the
// SHA-256 of its bytes.
//
// Thread-safe (no shared state); never throws (except std::bad_alloc).

#include <cstdint>
#include <expected>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "hrgbench/session/session_record.hpp"

namespace hrgbench::results {

struct RunRow {
  int run_id = 0;
  std::string status;                           // "complete", "aborted", ...
  std::optional<double> commanded_omega_rad_s;  // plan
  std::optional<double> free_run_s;             // plan
  std::optional<double> omega_rad_s;            // measured Ω given to the estimator
  std::optional<double> omega_std_error_rad_s;  // its standard error
  std::optional<double> earth_rate_rad_s;
  std::optional<double> temperature_start_c, temperature_end_c;
  std::optional<double> frequency_start_hz, frequency_end_hz;
  std::optional<std::int64_t> samples;
  std::int64_t drops = 0;  // sequence gaps + kernel drops + bad frames
};

// δ1..δ6 (1/s, "1" for δ2, rad/s for δ5 and δ6), ξ1..ξ4 ("1"), residual_rms ("unit of y") and
// the engineering quantities (τ, Q, splits, ... in their units; "1" where dimensionless): every
// row has a unit, never "".
// std is absent when the estimator did not give one; value is absent when not determined.
struct ParameterRow {
  std::string name;
  std::optional<double> value;
  std::optional<double> std;
  std::string unit;
};

struct LimitRow {
  std::string quantity;
  std::optional<double> min, max, value, std;
  std::string status;  // PASS, FAIL, NOT_EVALUATED ...
  std::string message;
};

struct SessionRow {
  std::string id;
  std::string serial;
  std::string station;
  std::string operator_name;  // "operator" in session.json when recorded; empty otherwise
  std::string software_version;
  std::string station_sha256, sequence_sha256, limits_sha256;
  // [sequence] name and [limits] name / product of the config copies in the folder
  // (config/sequence.toml, config/limits.toml); "" when there is no copy or it does not load.
  std::string sequence_name, limits_name, product;
  std::string fixture_position;        // fixture.position of a fixture's unit; "" otherwise
  std::string started_utc, ended_utc;  // canonical UTC text (utc_text.hpp); ended "" if absent
  std::string outcome;                 // PASS, FAIL, ERROR, ABORTED
  std::string reason;
  int exit_code = 0;
  int complete_runs = 0;
  std::string path;  // the session folder, absolute
  std::string content_sha256;
  std::vector<RunRow> runs;
  std::vector<ParameterRow> parameters;
  std::vector<LimitRow> limits;
  std::vector<std::string> warnings;
};

// The rows of a closed record. Errors (the message names the file and the field): the record is
// not closed (a session still running or interrupted has no outcome yet: resume it first); its
// started.utc or ended.utc is not an ISO 8601 time with a zone.
std::expected<SessionRow, std::string> ToSessionRow(const session::SessionRecord& record);

// session::ReadSessionRecord(dir) then ToSessionRow. Errors (the message names the file and the
// field): unreadable, not a session, a damaged field, not closed.
std::expected<SessionRow, std::string> ReadSessionRow(const std::filesystem::path& dir);

}  // namespace hrgbench::results
