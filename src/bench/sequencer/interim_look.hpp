#pragma once
// The sequence's [adaptive] looks (internal to the sequencer): a unit's record estimated and
// judged as its session would close with it, from its complete runs and, within a run, the samples
// of the run being captured so far; whether that verdict can still change; and the thread the
// looks run on.
//
// Why a thread: a look is a whole estimate (0.3 s of CPU for the production session, seconds for
// 6 × 1000 s), and meanwhile the table turns: its watchdog (1 s at the shipped stations) wants a
// heartbeat, the capture rings want draining and the operator's Abort wants an answer. So the
// sequencer starts a look and goes on keeping the table, and takes the answer when it is there.
// The look's thread holds a simulated clock's time still while it works (Clock::
// AttachCurrentThread) and estimates on that one thread (no joins, so VirtualTimeClock never parks
// it): in virtual time a look takes no time, and a simulated session is the same on a busy
// machine as on an idle one.

#include <atomic>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <semaphore>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "hrgbench/analysis/next_run.hpp"
#include "hrgbench/analysis/recorded_estimate.hpp"
#include "hrgbench/analysis/session_judge.hpp"
#include "hrgbench/config/limits_config.hpp"
#include "hrgbench/hw/clock.hpp"
#include "hrgbench/session/session_record.hpp"

namespace hrgbench::bench::internal {

// A unit's complete runs as recorded on disk (and, at a look within a run, the run so far),
// estimated and judged against the limits: what its session closes with, and (the sequence's
// [adaptive]) what it would close with now.
struct LaneJudgement {
  std::optional<std::string> error;  // the record cannot be read back, or has no complete run
  int complete_runs = 0;             // the partial run counted
  RecordedEstimate estimate;
  std::optional<session::SessionRecord> record;  // what the estimate was judged with
  std::optional<SessionJudgement> judgement;
  // RankNextRuns: one score per candidate (analysis/next_run.hpp); empty: no preference.
  std::vector<double> next_run_scores;
};

// The run being captured, as its record holds it so far (the samples in the record's own I/Q
// convention, as its CSV has them), with Ω and its standard error from the table's readings so far.
struct PartialRun {
  int run_id = 0;
  double omega_rad_s = std::numeric_limits<double>::quiet_NaN();
  double omega_std_rad_s = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> t_s;
  std::vector<double> y;  // y1..y4 of each sample in turn
};

// `plan_cut_short`: runs still planned are not a defect of the record (the unit ended early, or
// the session is still going). Judged against `limits` (the file's, or an interim look's).
// `threads`: the estimator's (0: the hardware's).
LaneJudgement JudgeLane(const std::filesystem::path& dir, bool plan_cut_short,
                        const LimitsConfig& limits, const PartialRun* partial = nullptr,
                        int threads = 0);

// The candidates ranked for a unit whose verdict is still open (into judged.next_run_scores; left
// empty when it is decided, or nothing is undecided): its complete runs as the record holds them
// (the measured Ω, the samples made) are the runs made.
void RankNextRuns(LaneJudgement& judged, std::span<const NextRunCandidate> candidates);

// Why a verdict can no longer change with more data, or nothing (DecidedWhy in interim_look.cpp).
std::optional<std::string> DecidedWhy(const estimator::EstimateSummary& estimate,
                                      const std::optional<Verdict>& verdict);

// One look at a time on its own thread (above). Owner thread only, except the look itself.
class LookWorker {
 public:
  explicit LookWorker(hw::Clock& clock) : clock_(clock) {}
  ~LookWorker();  // waits for a look in progress
  LookWorker(const LookWorker&) = delete;
  LookWorker& operator=(const LookWorker&) = delete;

  // A look started and not yet taken.
  bool Busy() const { return thread_.joinable(); }
  // Starts `look` (not Busy()); `tag` comes back with its answer (e.g. the unit's index).
  void Start(std::size_t tag, std::function<LaneJudgement()> look);
  // The finished look's tag and answer, once; nothing while it runs or when none was started.
  std::optional<std::pair<std::size_t, LaneJudgement>> TakeIfDone();

 private:
  hw::Clock& clock_;
  std::thread thread_;
  std::atomic<bool> done_{false};
  std::binary_semaphore attached_{0};  // the look's thread holds the clock
  std::size_t tag_ = 0;
  LaneJudgement answer_;
};

}  // namespace hrgbench::bench::internal
