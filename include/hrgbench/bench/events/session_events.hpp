#pragma once
// What a session tells a second program as it goes: the events of the event stream (issue 11 §1),
// made from the sequencer's callbacks and the session's result. The transport is EventStream
// (event_stream.hpp); the format, with an example of every type, is in docs/reference/events.md.
//
// Types (format version kEventFormatVersion), in the order a session produces them:
//   session_started  unit, station, station_kind, sequence, limits, session (its folder), resume,
//                    software_version, plan [{run_id, omega_rad_s, free_run_s, sample_rate_hz,
//                    samples}]
//   phase            run, run_count, run_id, omega_rad_s, phase: warm-up | settle | excite | ready
//                    | release | capture | stop | estimate | prompt (on every change)
//   progress         run, run_count, run_id, omega_rad_s, phase, samples, samples_expected,
//                    samples_lost, elapsed_s, remaining_s, table_rate_rad_s (at most one per
//                    min_progress_period_s of wall time, and at each phase change)
//   samples          run_id, stride, t_s [..], y [[y1, y2, y3, y4] ..]: the run's samples
//                    decimated (every stride-th), sent with the progress events
//   prompt           id, at (start | before run N | end), text, image (a data: URI or null): an
//                    operator prompt is open (the table at zero); answer it (the panel: POST
//                    /api/prompt) or abort the session
//   prompt_answered  id, answer (confirm | abort), by, how (panel | terminal | auto)
//   log              message: a line the sequencer logged
//   warning          message: a flagged or rejected run as it ends; the estimator's warnings
//   run_result       run_id, status (complete | rejected | aborted), reason, samples,
//                    samples_expected, omega_rad_s, omega_std_error_rad_s, omega_source,
//                    sequence_gaps, kernel_drops, bad_frames, temperature_{start,end}_c
//   estimate         estimate: the estimate as session.json records it (outcome.estimate)
//   limit            quantity, status, value, std, min, max, message: one per declared limit
//   fit_check        run, name, status, value, max, message: one per check of the fit
//   outcome          outcome (PASS | FAIL | ERROR | ABORTED), reason, exit_code, complete_runs,
//                    failed_limits [names], session
//   report           path (null when none was written)
// A fixture's stream (several units on the table) has session_started (unit "fixture"), then
//   fixture_started  units [{position, serial, session (its folder in the fixture's)}]
//   phase, progress, log as above (the table's, every unit's together; no samples)
//   unit_run_result  unit (index), position, serial, and run_result's fields
//   unit_outcome     unit, position, serial, outcome, reason, exit_code, complete_runs,
//                    failed_limits, session, report (the unit's report, null when none)
//   outcome          the fixture's: the worst unit's outcome (session: the fixture's folder)
//   end              events_published, events_lost (written by EventStream::Close)
//
// Threads: the callbacks Attach installs run on the sequencer's thread and only build small JSON
// objects and queue them (EventStream::Publish never waits for the reader); the other methods on
// the caller's thread, before and after RunSession. Not thread-safe otherwise.

#include <chrono>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hrgbench/bench/events/event_stream.hpp"
#include "hrgbench/bench/sequencer/sequencer.hpp"
#include "hrgbench/config/bench_configs.hpp"

namespace hrgbench::bench {

struct SessionEventOptions {
  // Progress events (with the samples gathered since the last) at most this often, wall time:
  // 5 Hz moves a progress bar smoothly and costs a reader ~1 kB/s.
  double min_progress_period_s = 0.2;
  // Points of each run's live plot: the samples are decimated to about this many per run.
  std::uint64_t plot_points_per_run = 400;
};

class SessionEventPublisher {
 public:
  SessionEventPublisher(EventStream& stream, SessionEventOptions options = {});

  // Before RunSession/ResumeSession.
  void SessionStarted(const BenchConfigs& configs, const std::string& unit_serial,
                      const std::string& session_dir, bool resume,
                      const std::string& software_version);
  // Installs on_progress, on_log, on_samples, on_run_end and on_prompt, each calling the one
  // already set (if any) first. `options` and this publisher must outlive the session.
  void Attach(RunnerOptions& options);
  // After the session: warnings, the estimate, each limit, the outcome.
  void SessionFinished(const SessionResult& result);
  // After the report was (or was not) written: empty = none.
  void ReportWritten(const std::string& report_path);
  // The report will be at `report_path` once the job `pid` has written it (report/job.json).
  void ReportBeingWritten(const std::string& report_path, long pid);

  // A fixture's: after SessionStarted, the units by position ({position, serial, session}).
  void FixtureStarted(nlohmann::json units);
  // Installs on_progress, on_log and on_unit_run_end for a fixture (`units` as FixtureStarted's;
  // unit i is the session's i-th unit). `options` and this publisher must outlive the session.
  void AttachFixture(RunnerOptions& options, nlohmann::json units);
  // One unit's result and report (empty: none), after the session.
  void UnitFinished(std::size_t unit, const SessionResult& result, const std::string& report);
  // The fixture's outcome (the worst unit's) with its exit code.
  void FixtureFinished(OutcomeKind outcome, int exit_code, const std::string& reason,
                       const std::string& fixture_dir);

 private:
  void OnProgress(const Progress& p);
  void OnSamples(int run_id, std::span<const GyroSampleRecord> samples);
  void OnRunEnd(int run_id, const RunEnd& end, std::uint64_t samples);
  void FlushSamples();
  nlohmann::json RunResultEvent(const char* type, int run_id, const RunEnd& end,
                                std::uint64_t samples) const;
  nlohmann::json units_ = nlohmann::json::array();  // a fixture's units, by index

  EventStream& stream_;
  SessionEventOptions options_;
  std::vector<std::uint64_t> samples_expected_;  // per run id (index run_id - 1)
  std::string last_phase_;
  int last_run_id_ = -1;
  std::chrono::steady_clock::time_point last_progress_{};
  // The current run's decimated samples not yet sent.
  int plot_run_id_ = 0;
  std::uint64_t plot_stride_ = 1;
  std::uint64_t plot_seen_ = 0;
  nlohmann::json plot_t_ = nlohmann::json::array();
  nlohmann::json plot_y_ = nlohmann::json::array();
};

// The phase name the stream uses for a sequencer phase ("table" is "settle"; the rest as is).
std::string EventPhaseName(std::string_view sequencer_phase);

}  // namespace hrgbench::bench
