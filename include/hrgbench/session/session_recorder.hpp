#pragma once
// SessionRecorder: writes a bench session in the estimator's session format
// (hrgbench/session/session.hpp) plus the bench's metadata, so that a crash, kill -9 or power loss
// leaves a readable session holding every completed run, and `hrg-bench resume` can continue it.
//
//   <dir>/session.json               rewritten atomically (temp, fsync, rename, fsync dir) at
//                                    Create, BeginRun, EndRun, Close and OpenForResume
//   <dir>/runs/run-NNN.csv.partial   the open run, streamed while it runs (buffered; written out at
//                                    least every flush_interval_ns, not fsynced: forensic only)
//   <dir>/runs/run-NNN.csv           a finished run: the .partial fsynced and renamed at EndRun
//   <dir>/runs/run-NNN.csv.interrupted  a .partial found by OpenForResume (the process died)
//   <dir>/runs/run-NNN.csv.attempt-K    an earlier finished attempt of a run that was run again
//   <dir>/can/session.log            every CAN frame handed to AppendCanFrames, candump -L format,
//                                    one log for the whole session (frames between runs included,
//                                    so canplayer replays the session as it happened); fsynced at
//                                    every EndRun and at Close
//
// session.json, beyond the estimator's keys (format, version, unit.serial, sample_rate_hz, runs[]):
//   "state": "running" | "closed"   "running" in a directory nobody is writing: the process died
//   "station": {"name"}, "software": {"version"}, "realtime": "<status>",
//   "config_sha256": {"station", "sequence", "limits"}, "simulation": {...} (when given),
//   "started": {"utc": "2024-05-01T12:00:00.123456Z", "monotonic_ns": N}, "ended": {...},
//   "resumed_at": [{"utc", "monotonic_ns", "previous_state", "previous_outcome"}],
//   "can_log": {"file": "can/session.log", "interface": "can0"},
//   "prompts": [{"id", "at", "text", "image_sha256", "shown": {utc, monotonic_ns}, "answer",
//                "by", "how", "answered": {...}, "reason" (interrupted only)}],
//   "outcome": {"kind", "exit_code", "reason", "failed_parameters": [...], "estimate": {...}}
//   runs[i]: "plan": {commanded_omega_rad_s, a, b, theta_rad, free_run_s, sample_rate_hz},
//            "start": {RunStart fields, "utc"}, "end": {RunEnd fields, "samples", "utc"},
//            "attempts": [earlier attempts: {"status", "reason", "file", "start", "end"}]
//   runs[i].omega_rad_s: the commanded Ω until EndRun, then RunEnd::omega_rad_s (measured table
//   rate + Earth rate) when finite. sample_rate_hz (top level) is the first planned run's.
//
// Run CSV columns: t_s,y1,y2,y3,y4,[freq_hz,][omega_meas_rad_s,]seq[,temp_c] (extra columns in name
// order, as session::WriteRunCsv writes them), numbers in shortest round-trip form: a run read back
// with session::ReadRunCsv is bit-identical to what was appended.
//
// Threads: one non-real-time thread calls every method (the capture thread only fills a queue that
// thread drains). Not thread-safe. Nothing here is real-time safe: it allocates, formats, writes
// and fsyncs.
//
// Failures: every method returns std::expected and never throws (except std::bad_alloc). An I/O
// failure (disk full, read-only, EIO) leaves every run that was already final intact, and the last
// good session.json in place; the caller records the session as ERROR (Close, which may itself fail
// on a full disk: session.json then still says "state": "running", which reads as a crash, not as
// a success). After an I/O failure during a run the run is closed (its .partial left for forensics)
// and further BeginRun calls are allowed, so the caller can try to Close cleanly.

#include <cstddef>
#include <cstdint>
#include <expected>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hrgbench/session/candump_log.hpp"
#include "hrgbench/session/session_outcome.hpp"
#include "hrgbench/session/session_record_types.hpp"

namespace hrgbench::bench {

struct RecorderOptions {
  // The open run's .partial (and the CAN log) are written out (write(2)) at least this often when
  // samples or frames arrive, and whenever 1 MiB is buffered: what a kill -9 can lose of the open
  // run. Completed runs lose nothing either way.
  std::int64_t flush_interval_ns = 200'000'000;
};

class SessionRecorder {
 public:
  SessionRecorder(SessionRecorder&&) noexcept;
  SessionRecorder& operator=(SessionRecorder&&) noexcept;
  // Writes buffered data out (no fsync) and closes the files. Does not Close() the session: a
  // recorder destroyed without Close() leaves a session that reads as interrupted ("running").
  ~SessionRecorder();

  // Creates `dir` (and missing parents), refusing an existing non-empty directory
  // (kDirectoryNotEmpty); validates the header (kInvalidArgument: empty serial or station, no runs,
  // run ids < 1 or repeated, non-finite plan values, free_run_s or sample_rate_hz <= 0, bad
  // interface name); writes session.json ("state": "running", every run "planned") and opens the
  // CAN log. Blocks on fsync.
  static std::expected<SessionRecorder, RecordError> Create(const std::filesystem::path& dir,
                                                            const SessionHeader& header,
                                                            const RecorderOptions& options = {});

  // Reopens a session this recorder wrote (kBadSession otherwise: missing or invalid session.json,
  // no "state" or a run without "plan"). Every run left "running" becomes "interrupted" (an
  // attempt recorded in "attempts"); every runs/*.csv.partial is renamed to *.csv.interrupted; a
  // torn last line of the CAN log is cut; a "resumed_at" entry is appended (with the previous
  // state and outcome, which is removed), and "state" is "running" again. Then RemainingRunIds()
  // are the runs still to do, in plan order. Blocks on fsync. `operator_name` (non-empty): who
  // resumed it, recorded in its "resumed_at" entry, and as the record's "operator" when the start
  // recorded none.
  static std::expected<SessionRecorder, RecordError> OpenForResume(
      const std::filesystem::path& dir, const RecorderOptions& options = {},
      const std::string& operator_name = {});

  // Opens run `run_id` (a planned run that is not complete; kWrongState if a run is open, the
  // session is closed, or the run is complete): runs/run-NNN.csv.partial is created and
  // session.json records the run as "running" with `start`. A run that had ended before (aborted,
  // rejected) has its CSV renamed to .attempt-K and its entry kept in "attempts".
  std::expected<void, RecordError> BeginRun(int run_id, const RunStart& start);

  // Appends samples to the open run (kWrongState without one). The whole batch is checked first
  // and refused (kInvalidArgument, nothing written) if a t_s is not finite or not strictly after
  // the previous sample, or a y or an enabled optional column is not finite.
  std::expected<void, RecordError> AppendSamples(std::span<const GyroSampleRecord> samples);

  // Makes the open run final: the .partial is written out, fsynced and renamed to run-NNN.csv, the
  // CAN log fsynced, then session.json rewritten with the run's status and `end`. Refused with the
  // run still open (kInvalidArgument) when status is not complete/aborted/rejected, a non-complete
  // run has no reason, or a complete run has a non-finite omega_rad_s. On an I/O failure the run
  // is closed and its status in session.json stays "running".
  std::expected<void, RecordError> EndRun(const RunEnd& end);

  // Hands raw CAN frames to the session's candump log (any time between Create and Close).
  std::expected<void, RecordError> AppendCanFrames(std::span<const LoggedCanFrame> frames);

  // An operator prompt: BeginPrompt appends {id, at, text, image_sha256, shown} to session.json's
  // "prompts" (so a record of a process that died while the prompt was open shows it open);
  // EndPrompt adds {answer, by, how, answered} to it. kWrongState when a run or another prompt is
  // open (BeginPrompt) or none is (EndPrompt); kInvalidArgument for an empty id or an answer not
  // one of the kPrompt* strings. Blocks on fsync.
  std::expected<void, RecordError> BeginPrompt(const PromptShown& prompt);
  std::expected<void, RecordError> EndPrompt(const PromptAnswered& answer);

  // Ends the session: an open prompt is ended "interrupted" and an open run "aborted", both with
  // the outcome's reason; the CAN log is
  // synced and closed; session.json gets "state": "closed", "ended" and "outcome". kInvalidArgument
  // (nothing written) when a non-PASS outcome has no reason. After Close (even a failed one) every
  // method but the accessors returns kWrongState.
  std::expected<void, RecordError> Close(const SessionOutcome& outcome);

  const std::filesystem::path& directory() const noexcept;
  std::vector<RecordedRun> Runs() const;            // every planned run, plan order
  std::vector<int> CompleteRunIds() const;          // status complete
  std::vector<int> RemainingRunIds() const;         // not complete, plan order
  std::optional<int> open_run_id() const noexcept;  // the run between BeginRun and EndRun
  std::uint64_t samples_in_open_run() const noexcept;

  class Impl;  // src/session/session_recorder_impl.hpp

 private:
  explicit SessionRecorder(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace hrgbench::bench
