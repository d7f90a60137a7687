#pragma once
// State shared by the steps of one session (internal to the sequencer): the table's part, and one
// lane per unit on it.

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <expected>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "bench/sequencer/interim_look.hpp"
#include "hrgbench/bench/capture/capture.hpp"
#include "hrgbench/bench/sequencer/sequencer.hpp"
#include "hrgbench/session/session_recorder.hpp"

namespace hrgbench::bench::internal {

// Why a step stopped. kNone: go on. A step returns the table's (every unit's) stop; a unit's own
// stop ends only its lane (SessionContext::EndUnit).
enum class StopKind { kNone, kError, kAborted };

struct StepOutcome {
  StopKind stop = StopKind::kNone;
  std::string reason;
  static StepOutcome Ok() { return {}; }
  static StepOutcome Error(std::string why) { return {StopKind::kError, std::move(why)}; }
  static StepOutcome Aborted(std::string why) { return {StopKind::kAborted, std::move(why)}; }
  bool ok() const { return stop == StopKind::kNone; }
};

// One unit's part of the session.
struct UnitLane {
  const UnitHardware* hw = nullptr;
  SessionRecorder* recorder = nullptr;
  std::filesystem::path dir;
  std::string label;        // "A SN-1: " before its log lines when the table carries several
  std::set<int> remaining;  // run ids still to make
  bool ended = false;       // its session is closed; it takes no further part
  // Its verdict could no longer change (the sequence's [adaptive]): it took no further run.
  std::optional<EarlyEnd> ended_early;
  // The estimate and verdict that decided it: its record takes no further run, so the session
  // closes with them instead of estimating the same runs again.
  std::shared_ptr<LaneJudgement> decided;
  SessionResult result;  // its warnings as they come; the rest once it ends
  std::vector<LoggedCanFrame> logged_scratch;

  bool Takes(int run_id) const { return !ended && remaining.contains(run_id); }
  // Its runs the record holds as complete.
  int CompleteRuns() const {
    int complete = 0;
    for (const RecordedRun& run : recorder->Runs()) complete += run.status == kRunComplete ? 1 : 0;
    return complete;
  }
  // The planned free run of the shortest of them (0 when none).
  double ShortestCompleteRunS() const {
    double shortest = 0.0;
    bool any = false;
    for (const RecordedRun& run : recorder->Runs()) {
      if (run.status != kRunComplete) continue;
      shortest = any ? std::min(shortest, run.plan.free_run_s) : run.plan.free_run_s;
      any = true;
    }
    return shortest;
  }
};

struct SessionContext {
  const BenchConfigs* configs = nullptr;
  const BenchHardware* hw = nullptr;
  const RunnerOptions* options = nullptr;
  std::vector<UnitLane> lanes;
  double earth_rate_rad_s = 0.0;
  std::int64_t start_ns = 0;        // hardware clock at the start of this invocation
  std::int64_t unix_offset_ns = 0;  // unix time = hardware clock + offset (CAN log stamps)
  std::int64_t last_progress_ns = 0;
  std::atomic<bool> stop_capture{false};  // set on the first interrupt; read by capture threads
  int run_index = 0;                      // 1-based, this invocation
  int run_count = 0;
  double remaining_free_run_s = 0.0;  // of the runs not yet captured
  // The sequence's [adaptive]: the limits with the interim looks' coverage factor, and the thread
  // the looks run on (interim_look.hpp).
  LimitsConfig interim_limits;
  std::unique_ptr<LookWorker> looks;
  // next_run = "most_informative": the units' rankings of the runs left after the last look, by
  // run id (summed over the units still measuring); the table's time from a run's start to its
  // release, summed over the runs made (what another run costs beyond its free run).
  std::map<int, double> next_run_scores;
  double run_overhead_s = 0.0;
  int runs_made = 0;

  bool Interrupted() const;
  // Who stopped the session, for the record: "aborted by operator" (SIGINT: Ctrl-C, the panel's
  // Abort) or "stopped by SIGTERM".
  std::string InterruptCause() const;
  void Log(std::string_view line) const;
  void Log(const UnitLane& lane, std::string_view line) const;
  void ReportProgress(const Progress& progress, bool force = false);
  double Seconds(std::int64_t from_ns) const;
  int LiveUnits() const;
  // Moves every frame the lane's monitor has received to its CAN log. Never blocks.
  StepOutcome PumpCanLog(UnitLane& lane);
  // Every live lane's; a lane whose log cannot be written is ended (its own fault).
  void PumpCanLogs();
  // Ends a lane on its own fault: its gyro stopped (and the table brought to zero rate first when
  // it was the last unit on it), its log completed, its session closed with the reason.
  void EndUnit(UnitLane& lane, const StepOutcome& why);
  // Closes a lane whose hardware is already safe (`made_safe` says how, for the log) with the
  // stop's reason, its log completed first.
  void CloseStopped(UnitLane& lane, const StepOutcome& why, std::string_view made_safe);
};

StepOutcome WaitForWarmup(SessionContext& ctx);

// The look started on ctx.looks, waited for while the table is kept (its heartbeat, the CAN logs,
// every `poll_ns`); an interrupt or a table error ends the wait (the look finishes on its own).
std::expected<std::pair<std::size_t, LaneJudgement>, StepOutcome> AwaitLook(SessionContext& ctx,
                                                                            std::int64_t poll_ns);
// A look's answer for `lane` during or after run `run_id`: if its verdict can no longer change
// (DecidedWhy), the lane is decided (ended_early, announced, logged) and takes no further run;
// true then. `within_run_s`: how far into the run's free run the look saw (kAfterTheRun: the whole
// run). `whole_record`: the look estimated exactly what the record holds, so the session may close
// with it.
inline constexpr double kAfterTheRun = std::numeric_limits<double>::quiet_NaN();
bool ApplyLook(SessionContext& ctx, UnitLane& lane, int run_id, LaneJudgement now,
               double within_run_s, bool whole_record);
// "decided after run 2 of 12", "decided 15 s into run 8 of 12".
std::string DecidedWhen(const EarlyEnd& end);
// The sequence's operator prompts at `at` (before run `run_id` for kBeforeRun), in file order
// (prompt_step.cpp).
StepOutcome AskOperator(SessionContext& ctx, PromptPoint at, int run_id = 0);
StepOutcome RunOne(SessionContext& ctx, const SequenceRun& run, int run_id);

// Puts the table in its safe state (zero rate) and every gyro in its own (stopped). Never throws.
void MakeSafe(const BenchHardware& hw) noexcept;
// After MakeSafe: the table's rate reported (phase "stopping") until it reads zero or a bound.
void WatchTableStop(SessionContext& ctx);
// Stops one gyro. Never throws.
void StopGyro(const UnitHardware& unit) noexcept;

}  // namespace hrgbench::bench::internal
