#pragma once
// The session directory: the interface between capture (the bench) and estimation.
//
//   <session>/session.json            {"format": "hrgbench-session", "version": 1, ...}
//   <session>/runs/run-001.csv, ...   header containing at least t_s,y1,y2,y3,y4 (any order, other
//                                     columns allowed), one line per sample, t_s strictly
//                                     increasing, values with round-trip precision
//
// Run CSV, exactly: comma-separated, no quoting, no spaces around fields; line 1 is the header
// (non-empty, unique column names; a UTF-8 BOM is ignored); every further line is one sample with
// exactly as many fields as the header; every field is a finite decimal number as accepted by
// std::from_chars (so no leading '+' or blanks; "nan", "inf" are rejected). Lines end in "\n" or
// "\r\n"; the final line ending is optional; an empty line is an error. Values are written in the
// shortest form that reads back to the identical double (std::to_chars without precision, like
// Python's repr), which round-trips exactly just as %.17g does but keeps "0.01" as "0.01".
//
// session.json keys read: format, version, unit.serial, sample_rate_hz, runs[].{id, file,
// omega_rad_s, status, end.omega_std_error_rad_s (optional)}, electronics.iq_convention (optional:
// "minus-sine" | "plus-sine", estimator/iq_convention.hpp; a session from before it was recorded is
// read as the model's "minus-sine", with a note; any other value is an error). Every other key
// (station, config hashes, temperature, "simulation" truth...) is kept verbatim in `document` and
// written back unchanged. Runs whose status is not "complete" are skipped with a warning. Every
// error names the file, the line (1-based, 0 when not applicable) and the field.
//
// Bounds (refused with an error naming the file, before anything large is allocated or any
// recursive parse starts): see the constants below. The reader refuses what exceeds them and the
// writer refuses to write it, so a file the writer wrote always reads back.
//
// Writing is atomic per file (temporary file in the same directory, fsync, rename, fsync of the
// directory), so a crash leaves either the old or the new file, never half of one.

#include <Eigen/Core>
#include <cstddef>
#include <expected>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hrgbench/estimator/iq_convention.hpp"
#include "hrgbench/estimator/run_data.hpp"

namespace hrgbench::session {

inline constexpr const char* kFormatName = "hrgbench-session";
inline constexpr int kFormatVersion = 1;

// session.json: at most 64 MiB (a bench session is tens of KiB; every resume and attempt adds
// about 1 KiB) and at most 64 levels of nested arrays and objects (a bench session is under 10
// deep: {} → runs[] → run → attempts[] → attempt → start → ...). The depth is checked on the text
// before it is parsed, because the JSON library recurses per level: 100 000 levels overflowed the
// stack of hrg-estimate.
inline constexpr std::size_t kMaxSessionJsonBytes = std::size_t{64} << 20;
inline constexpr std::size_t kMaxSessionJsonDepth = 64;
// Entries in "runs" (a sequence has at most 1000 runs, and each may be listed once).
inline constexpr std::size_t kMaxSessionRuns = 1000;
// unit.serial, runs[].status and runs[].file: at most 255 bytes, no control characters
// (U+0000..U+001F, U+007F): they are printed in reports and used in file names.
inline constexpr std::size_t kMaxSessionNameBytes = 255;
// Run CSV: at most 4 GiB (1e7 samples of 8 columns at full precision are about 2 GB), at most
// 1e7 samples (the configs' bound per run), at most 64 columns, lines of at most 4096 bytes (64
// values of at most 24 characters and their commas fit in 1600).
inline constexpr std::size_t kMaxRunCsvBytes = std::size_t{4} << 30;
inline constexpr std::size_t kMaxRunCsvSamples = 10'000'000;
inline constexpr std::size_t kMaxRunCsvColumns = 64;
inline constexpr std::size_t kMaxRunCsvLineBytes = 4096;

struct SessionError {
  std::filesystem::path file;  // the file at fault
  std::size_t line = 0;        // 1-based line in that file; 0 when the error is not about a line
  std::string field;           // JSON key path ("runs[2].omega_rad_s", array indices 0-based as in
                               // jq) or CSV column ("t_s"; "column 6" past the header's end)
  std::string message;         // what is wrong, with the offending value

  // "<file>:<line>: field '<field>': <message>" (line and field omitted when not applicable).
  std::string ToString() const;
};

// One run's samples as stored in its CSV.
struct RunSamples {
  std::vector<double> t_s;
  Eigen::Matrix4Xd y;  // y(:, k) = (y1..y4) at t_s[k]
  // Further columns (seq, omega_meas_rad_s, temp_c, ...), by header name, same length as t_s.
  std::map<std::string, std::vector<double>> extra_columns;

  std::size_t size() const { return t_s.size(); }
};

// One entry of session.json "runs".
struct RunEntry {
  int id = 0;
  std::string file;  // relative to the session directory, e.g. "runs/run-001.csv"
  double omega_rad_s = 0.0;
  std::string status = "complete";
  // end.omega_std_error_rad_s when the bench recorded it (the standard error of Ω); NaN otherwise.
  double omega_std_rad_s = std::numeric_limits<double>::quiet_NaN();
};

struct Session {
  std::string serial;  // unit.serial
  double sample_rate_hz = 0.0;
  std::vector<RunEntry> runs;  // every run listed, whatever its status
  // electronics.iq_convention: the sign convention of the recorded quadrature channels (y2, y4).
  // The writer always records it; ToRunData converts to the model's.
  estimator::IqConvention iq_convention = estimator::IqConvention::kMinusSine;
  nlohmann::json document;  // the whole session.json, unknown keys included

  // Samples of the runs that were loaded (status "complete"), parallel to `loaded_run_ids`.
  std::vector<int> loaded_run_ids;
  std::vector<RunSamples> loaded_samples;
  std::vector<std::string> warnings;  // e.g. "run 3 skipped: status 'aborted'"
  // What the reader assumed, or did to the data, that is not a problem: "no
  // electronics.iq_convention: read as minus-sine", "plus-sine: y2, y4 negated for the fit".
  std::vector<std::string> notes;
};

struct ReadOptions {
  // Runs with fewer samples are an error (the estimator's need: 2 for ML, the derivative window
  // for the paper's method).
  std::size_t min_samples_per_run = 2;
  // Load the CSV data (false: session.json only).
  bool load_samples = true;
  // Keep the run CSVs' extra columns (RunSamples::extra_columns). false: only t_s and y1..y4 are
  // kept (what the estimate needs; each extra column is 8 bytes per sample), the extra values
  // still checked as the format requires.
  bool extra_columns = true;
  // The caller cut the plan short (the sequence's [adaptive], before the record says so): runs
  // left "planned" are not warned about. A record whose outcome.ended_early says so needs no flag.
  bool plan_cut_short = false;
};

// Reads `dir`/session.json, validates every key this reader uses, then (options.load_samples) the
// CSV of every run whose status is "complete". The whole session is loaded or an error returned;
// never throws (except std::bad_alloc). Run files must stay inside `dir` lexically ("runs/x.csv",
// not "../x.csv" or an absolute path); symbolic links are not resolved. Thread-safe (no shared
// state). A read concurrent with a write sees each file either old or new, never half-written, but
// session.json and the CSVs need not be from the same write then.
std::expected<Session, SessionError> ReadSession(const std::filesystem::path& dir,
                                                 const ReadOptions& options = {});

// Reads the CSV of every complete run of `session` (as ReadSession returned it with
// options.load_samples false) in record order, handing each to `on_run` as soon as it is read: one
// run's samples in memory at a time, whatever the session's size (run_spool.hpp keeps them). Stops
// at the first error, the reader's or the one `on_run` returns. ReadSession loads its runs so.
using RunSamplesSink =
    std::function<std::expected<void, SessionError>(const RunEntry& entry, RunSamples&& samples)>;
std::expected<void, SessionError> ReadEachRun(const std::filesystem::path& dir,
                                              const Session& session, const ReadOptions& options,
                                              const RunSamplesSink& on_run);

// Reads one run CSV (format above), the whole file at once with std::from_chars: 14-20 ms for
// 100 000 lines of six columns (9 MB) on the development machine. Fewer than `min_samples_per_run`
// samples is an error (line 0, field "t_s"). `keep_extra_columns` as ReadOptions::extra_columns.
// Memory: the file's text (≈ 85 bytes per sample of hrg-sim's runs) while it is parsed, then
// 40 bytes per sample (t_s, y) plus 8 per extra column kept. Never throws (except std::bad_alloc).
std::expected<RunSamples, SessionError> ReadRunCsv(const std::filesystem::path& path,
                                                   std::size_t min_samples_per_run = 2,
                                                   bool keep_extra_columns = true);

// The loaded runs as the estimator sees them (id, Ω from session.json, t_s, y), in load order.
// Ω is looked up by id in `runs`; a loaded id missing there (only possible in a hand-built Session)
// gets Ω = 0. y is in the model's I/Q convention: a session recorded in "plus-sine" has each
// channel conjugated (y2, y4 negated; estimator::ToModelConvention), as the reader's note says.
std::vector<estimator::RunData> ToRunData(const Session& session);
// The same, moving the samples out of `session` (its loaded_samples are left empty): no second
// copy of the session's samples, which is what an estimate of a long session cannot afford.
std::vector<estimator::RunData> ToRunData(Session&& session);
// One run as ToRunData converts it: Ω and its std from `entry`, the samples moved in, y in the
// model's convention.
estimator::RunData ToRunData(const RunEntry& entry, RunSamples&& samples,
                             estimator::IqConvention convention);

// Writes one run CSV atomically: header "t_s,y1,y2,y3,y4" followed by the extra columns in name
// order, values in shortest round-trip form (see above). Creates the parent directories. Refuses
// (SessionError, nothing written) what ReadRunCsv would reject: sizes that differ from t_s.size(),
// non-finite values, t_s not strictly increasing, extra column names that are empty, contain ',',
// '\r' or '\n', or repeat t_s/y1..y4. Zero samples is allowed (the minimum is the reader's choice).
std::expected<void, SessionError> WriteRunCsv(const std::filesystem::path& path,
                                              const RunSamples& samples);

// Writes session.json atomically from `session.document` after setting format, version,
// unit.serial, sample_rate_hz, electronics.iq_convention and runs from the typed fields. Unknown
// keys are kept, also inside a run entry (matched to `session.runs` by id). Keys come out in
// alphabetical order (nlohmann::json is a sorted map), 2-space indent. Creates `dir`. Refuses what
// ReadSession would reject: a document that is neither null nor an object, sample_rate_hz not
// finite and > 0, run id < 1 or repeated, a non-finite omega_rad_s, a run file outside `dir`.
std::expected<void, SessionError> WriteSessionJson(const std::filesystem::path& dir,
                                                   const Session& session);

// Creates `dir` and any missing parents, fsyncing the parent of each directory it creates, so the
// new entries survive a power loss (mkdir -p, durably).
std::expected<void, SessionError> CreateDirectoriesDurably(const std::filesystem::path& dir);

// fsync of a directory: without it a rename or a new entry in it may be lost on power failure even
// though the file's data was synced. An empty path means ".".
std::expected<void, SessionError> FsyncDirectory(const std::filesystem::path& dir);

// Atomic write of any small text file (temporary, fsync, rename, fsync directory). The parent
// directory must exist. The temporary (".<name>.tmp.<pid>.<n>") is removed on failure.
// Thread-safe; with concurrent writers of one path the last rename wins. Blocks on fsync (tens of
// ms on a busy disk): not for a real-time thread.
std::expected<void, SessionError> WriteFileAtomic(const std::filesystem::path& path,
                                                  const std::string& contents);

}  // namespace hrgbench::session
