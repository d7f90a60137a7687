#pragma once
// State shared by the steps of one session (internal to the sequencer).

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "hrgbench/bench/capture.hpp"
#include "hrgbench/bench/sequencer.hpp"
#include "hrgbench/bench/session_recorder.hpp"

namespace hrgbench::bench::internal {

// Why a step stopped the session. kNone: go on.
enum class StopKind { kNone, kError, kAborted };

struct StepOutcome {
  StopKind stop = StopKind::kNone;
  std::string reason;
  static StepOutcome Ok() { return {}; }
  static StepOutcome Error(std::string why) { return {StopKind::kError, std::move(why)}; }
  static StepOutcome Aborted(std::string why) { return {StopKind::kAborted, std::move(why)}; }
  bool ok() const { return stop == StopKind::kNone; }
};

struct SessionContext {
  const BenchConfigs* configs = nullptr;
  const BenchHardware* hw = nullptr;
  const RunnerOptions* options = nullptr;
  SessionRecorder* recorder = nullptr;
  double earth_rate_rad_s = 0.0;
  std::int64_t start_ns = 0;            // hardware clock at the start of this invocation
  std::int64_t unix_offset_ns = 0;      // unix time = hardware clock + offset (CAN log stamps)
  std::int64_t last_progress_ns = 0;
  std::atomic<bool> stop_capture{false};  // set on the first interrupt; read by the capture thread
  int run_index = 0;                    // 1-based, this invocation
  int run_count = 0;
  double remaining_free_run_s = 0.0;    // of the runs not yet captured
  std::vector<std::string> warnings;
  std::vector<hw::CanFrame> frame_scratch;
  std::vector<LoggedCanFrame> logged_scratch;

  bool Interrupted() const;
  // Who stopped the session, for the record: "aborted by operator" (SIGINT: Ctrl-C, the panel's
  // Abort) or "stopped by SIGTERM".
  std::string InterruptCause() const;
  void Log(std::string_view line) const;
  void ReportProgress(const Progress& progress, bool force = false);
  double Seconds(std::int64_t from_ns) const;
  // Moves every frame the monitor has received to the CAN log. Never blocks.
  StepOutcome PumpCanLog();
};

StepOutcome WaitForWarmup(SessionContext& ctx);
StepOutcome RunOne(SessionContext& ctx, const SequenceRun& run, int run_id);

// Puts the hardware in its safe state: table to zero rate, gyro stopped. Never throws.
void MakeSafe(const BenchHardware& hw) noexcept;

}  // namespace hrgbench::bench::internal
