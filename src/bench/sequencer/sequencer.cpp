#include "hrgbench/bench/sequencer/sequencer.hpp"

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <expected>
#include <optional>
#include <set>
#include <thread>

#include "bench/sequencer/interim_look.hpp"
#include "bench/sequencer/run_context.hpp"
#include "bench/sequencer/saved_configs.hpp"
#include "hrgbench/analysis/interim_looks.hpp"
#include "hrgbench/analysis/output_filter.hpp"
#include "hrgbench/analysis/recorded_estimate.hpp"
#include "hrgbench/analysis/recorded_frequency.hpp"
#include "hrgbench/analysis/session_judge.hpp"
#include "hrgbench/bench/capture/realtime_setup.hpp"
#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_record.hpp"
#include "hrgbench/session/session_record_keys.hpp"

namespace hrgbench::bench {
namespace internal {

bool SessionContext::Interrupted() const {
  return options->interrupts != nullptr && options->interrupts->load() > 0;
}

std::string SessionContext::InterruptCause() const {
  const int signal = options->interrupt_signal != nullptr ? options->interrupt_signal->load() : 0;
  return signal == SIGTERM ? "stopped by SIGTERM" : "aborted by operator";
}

void SessionContext::Log(std::string_view line) const {
  if (options->on_log) options->on_log(line);
}

void SessionContext::Log(const UnitLane& lane, std::string_view line) const {
  if (options->on_log) options->on_log(lane.label + std::string(line));
}

int SessionContext::LiveUnits() const {
  int live = 0;
  for (const UnitLane& lane : lanes) live += lane.ended ? 0 : 1;
  return live;
}

void SessionContext::ReportProgress(const Progress& progress, bool force) {
  if (!options->on_progress) return;
  const std::int64_t now = hw->clock->NowNs();
  if (!force &&
      now - last_progress_ns < static_cast<std::int64_t>(options->progress_period_s * 1e9))
    return;
  last_progress_ns = now;
  Progress p = progress;
  p.run_count = run_count;
  p.elapsed_s = Seconds(now);
  p.units_active = LiveUnits();
  p.unit_count = static_cast<int>(lanes.size());
  // Outside a capture the free-run time still ahead is the estimate (the capture knows better).
  if (p.phase != "capture") p.remaining_s = remaining_free_run_s;
  options->on_progress(p);
}

double SessionContext::Seconds(std::int64_t from_ns) const {
  return static_cast<double>(from_ns - start_ns) * 1e-9;
}

StepOutcome SessionContext::PumpCanLog(UnitLane& lane) {
  hw::CanBus* monitor = lane.hw->monitor;
  if (monitor == nullptr || lane.ended) return StepOutcome::Ok();
  std::vector<LoggedCanFrame>& logged = lane.logged_scratch;
  logged.clear();
  hw::CanFrame frame;
  hw::ReceiveInfo info;
  // Bounded: a babbling bus must not keep the sequencer from its other duties.
  for (int i = 0; i < 100000; ++i) {
    if (monitor->Receive(&frame, 0, &info) != hw::CanStatus::kOk) break;
    std::int64_t unix_ns = hw->clock->NowNs() + unix_offset_ns;
    if (info.timestamp_ns != 0) {
      if (lane.hw->monitor_stamps_on_bench_clock)
        unix_ns = info.timestamp_ns + unix_offset_ns;
      else if (info.timestamp_source == hw::TimestampSource::kSoftware)
        unix_ns = info.timestamp_ns;  // already CLOCK_REALTIME
    }
    logged.push_back({unix_ns, frame});
  }
  if (logged.empty()) return StepOutcome::Ok();
  if (auto appended = lane.recorder->AppendCanFrames(logged); !appended)
    return StepOutcome::Error("record: CAN log: " + appended.error().ToString());
  return StepOutcome::Ok();
}

void SessionContext::PumpCanLogs() {
  for (UnitLane& lane : lanes) {
    if (StepOutcome pumped = PumpCanLog(lane); !pumped.ok()) EndUnit(lane, pumped);
  }
}

void SessionContext::EndUnit(UnitLane& lane, const StepOutcome& why) {
  if (lane.ended) return;
  const bool last = LiveUnits() == 1;
  if (last) hw->table->SafeStop();
  StopGyro(*lane.hw);
  CloseStopped(lane, why, last ? "table commanded to zero rate, gyro stopped" : "gyro stopped");
}

void SessionContext::CloseStopped(UnitLane& lane, const StepOutcome& why,
                                  std::string_view made_safe) {
  // The safe-state commands and whatever came before them, in the log before it closes; a log
  // that cannot be written now changes nothing (the unit already stops with its reason).
  (void)PumpCanLog(lane);
  Log(lane, "stopping: " + why.reason + "; " + std::string(made_safe));
  SessionOutcome outcome;
  outcome.kind = why.stop == StopKind::kAborted ? OutcomeKind::kAborted : OutcomeKind::kError;
  outcome.reason = why.reason;
  lane.result.dir = lane.dir;
  lane.result.outcome = outcome.kind;
  lane.result.reason = why.reason;
  if (auto closed = lane.recorder->Close(outcome); !closed)
    lane.result.reason += "; record: cannot close: " + closed.error().ToString();
  lane.result.exit_code = ExitCode(lane.result.outcome);
  lane.ended = true;
}

void StopGyro(const UnitHardware& unit) noexcept {
  try {
    (void)unit.gyro->Stop();
  } catch (...) {
    // Only std::bad_alloc can get here.
  }
}

void MakeSafe(const BenchHardware& hw) noexcept {
  hw.table->SafeStop();
  for (const UnitHardware& unit : hw.units) StopGyro(unit);
}

// After a stop (an Abort, a fault), the table's measured rate as it comes down, reported as the
// phase "stopping" every 100 ms until it reads zero or the time a stop from the highest rate at
// the set acceleration would take (twice, + 2 s; at most 60 s) has passed: the operator sees the
// table reach rest instead of its last rate frozen on the screen (issue 26 §1). Reading only: the
// table was commanded to zero (SafeStop) before, and its watchdog stops it without a heartbeat.
void WatchTableStop(SessionContext& ctx) {
  if (!ctx.options->on_progress) return;
  constexpr double kRestRateRadS = 1e-3;  // "reads zero": the table's stable tolerance
  constexpr std::int64_t kPeriodNs = 100'000'000;
  const TableLinkConfig& table = ctx.configs->station.table;
  const double bound_s =
      std::min(2.0 * table.max_rate_rad_s / std::max(table.accel_rad_s2, 1e-3) + 2.0, 60.0);
  const std::int64_t end_ns = ctx.hw->clock->NowNs() + static_cast<std::int64_t>(bound_s * 1e9);
  Progress progress;
  progress.phase = "stopping";
  for (;;) {
    const auto status = ctx.hw->table->ReadStatus();
    if (!status) {
      ctx.Log("after the stop the table's rate cannot be read: " + status.error().message);
      return;
    }
    progress.table_rate_rad_s = status->measured_rate_rad_s;
    ctx.ReportProgress(progress, true);
    char rate[32];
    std::snprintf(rate, sizeof rate, "%.5f", status->measured_rate_rad_s);
    if (std::abs(status->measured_rate_rad_s) < kRestRateRadS) {
      ctx.Log(std::string("the table reads zero (") + rate + " rad/s): stopped");
      return;
    }
    if (ctx.hw->clock->NowNs() >= end_ns) {
      ctx.Log(std::string("the table still reads ") + rate + " rad/s after the stop");
      return;
    }
    ctx.hw->clock->SleepForNs(kPeriodNs);
  }
}

std::expected<std::pair<std::size_t, LaneJudgement>, StepOutcome> AwaitLook(SessionContext& ctx,
                                                                            std::int64_t poll_ns) {
  for (;;) {
    if (auto done = ctx.looks->TakeIfDone()) return std::move(*done);
    // The look is left to finish on its own (its thread is joined when the session ends).
    if (ctx.Interrupted())
      return std::unexpected(
          StepOutcome::Aborted(ctx.InterruptCause() + " while a unit's runs were judged"));
    if (auto fed = ctx.hw->table->Heartbeat(); !fed)
      return std::unexpected(StepOutcome::Error("rate table: " + fed.error().ToString()));
    ctx.PumpCanLogs();
    ctx.hw->clock->SleepForNs(poll_ns);
  }
}

std::string DecidedWhen(const EarlyEnd& end) {
  std::string when = "decided ";
  if (std::isfinite(end.within_run_s)) {
    char at[32];
    std::snprintf(at, sizeof at, "%.3g", end.within_run_s);
    when += std::string(at) + " s into run " + std::to_string(end.after_run);
  } else {
    when += "after run " + std::to_string(end.after_run);
  }
  return when + " of " + std::to_string(end.planned_runs);
}

bool ApplyLook(SessionContext& ctx, UnitLane& lane, int run_id, LaneJudgement now,
               double within_run_s, bool whole_record) {
  const AdaptiveStop& adaptive = ctx.configs->sequence.adaptive;
  if (lane.ended || lane.ended_early) return false;
  if (now.error || now.complete_runs < adaptive.min_runs || !now.judgement) return false;
  const std::optional<std::string> why =
      DecidedWhy(now.estimate.method.summary, now.judgement->verdict);
  char k_text[48];
  std::snprintf(k_text, sizeof k_text, "interim k = %.3g",
                ctx.interim_limits.decision.coverage_factor);
  if (!why) {
    // Within a run the looks come every few seconds: only the look after a run is logged.
    if (!std::isfinite(within_run_s))
      ctx.Log(lane, "after run " + std::to_string(run_id) + ": not decided yet at " + k_text +
                        " (" + now.judgement->reason + ")");
    return false;
  }
  const int planned = static_cast<int>(ctx.configs->sequence.runs.size());
  lane.ended_early =
      EarlyEnd{run_id, planned, *why, ctx.interim_limits.decision.coverage_factor, within_run_s};
  if (ctx.options->on_decided)
    ctx.options->on_decided(static_cast<std::size_t>(&lane - ctx.lanes.data()), *lane.ended_early);
  const std::size_t not_needed = lane.remaining.size() - (lane.remaining.contains(run_id) ? 1 : 0);
  ctx.Log(lane, DecidedWhen(*lane.ended_early) + " (" + *why + ", " + k_text +
                    "): " + std::to_string(not_needed) + " planned run(s) not needed");
  lane.remaining.clear();
  // Only an estimate of exactly what the record holds may close the session; one made within a
  // run saw the run so far, and the run's capture went on a moment longer.
  if (whole_record) lane.decided = std::make_shared<LaneJudgement>(std::move(now));
  return true;
}

}  // namespace internal

namespace {

using internal::SessionContext;
using internal::StepOutcome;
using internal::StopKind;
using internal::UnitLane;

using internal::LaneJudgement;

SessionResult Finish(SessionResult result) {
  result.exit_code = ExitCode(result.outcome);
  return result;
}

// How often the wait for a look between runs feeds the table's heartbeat and reads the CAN logs.
constexpr std::int64_t kLookPollNs = 20'000'000;

// The lane's runs still to make, as the next-run ranking sees them: in its own frame, each
// costing its free run and the table's time to reach it, as the runs made so far took it.
std::vector<NextRunCandidate> NextRunCandidates(const SessionContext& ctx, const UnitLane& lane) {
  std::vector<NextRunCandidate> out;
  const SequenceConfig& seq = ctx.configs->sequence;
  const double overhead_s = ctx.runs_made > 0 ? ctx.run_overhead_s / ctx.runs_made : 0.0;
  for (const int id : lane.remaining) {
    const SequenceRun& run = seq.runs[static_cast<std::size_t>(id - 1)];
    NextRunCandidate candidate;
    candidate.id = id;
    const double sign = lane.hw->axis_sign;
    candidate.plan.omega_rad_s = sign * (run.omega_rad_s + ctx.earth_rate_rad_s);
    candidate.plan.a = run.a;
    candidate.plan.b = run.b;
    candidate.plan.theta_rad = run.theta_rad;
    candidate.plan.sample_rate_hz = run.sample_rate_hz;
    candidate.plan.duration_s = run.free_run_s;
    candidate.table_s = run.free_run_s + overhead_s;
    out.push_back(candidate);
  }
  return out;
}

// The sequence's [adaptive], after run `run_id`: each unit still measuring whose verdict can no
// longer change takes no further run (RunPlanned then skips the runs nobody needs); with next_run =
// "most_informative" the others rank the runs left. The looks run on the session's look thread
// while this one keeps the table (interim_look.hpp).
StepOutcome DecideEarly(SessionContext& ctx, int run_id) {
  const AdaptiveStop& adaptive = ctx.configs->sequence.adaptive;
  ctx.next_run_scores.clear();
  if (!adaptive.stop_when_decided) return StepOutcome::Ok();
  for (UnitLane& lane : ctx.lanes) {
    if (lane.ended || lane.remaining.empty() || lane.CompleteRuns() < adaptive.min_runs) continue;
    std::vector<NextRunCandidate> candidates;
    if (adaptive.most_informative_next) candidates = NextRunCandidates(ctx, lane);
    ctx.looks->Start(static_cast<std::size_t>(&lane - ctx.lanes.data()),
                     [dir = lane.dir, limits = &ctx.interim_limits, candidates] {
                       LaneJudgement judged = internal::JudgeLane(dir, /*plan_cut_short=*/true,
                                                                  *limits, nullptr, /*threads=*/1);
                       if (!candidates.empty()) internal::RankNextRuns(judged, candidates);
                       return judged;
                     });
    auto now = internal::AwaitLook(ctx, kLookPollNs);
    if (!now) return now.error();
    const std::vector<double> scores = now->second.next_run_scores;
    if (internal::ApplyLook(ctx, lane, run_id, std::move(now->second), internal::kAfterTheRun,
                            /*whole_record=*/true))
      continue;
    // A unit still measuring: what it needs weighs in the table's next run.
    for (std::size_t c = 0; c < scores.size() && c < candidates.size(); ++c)
      ctx.next_run_scores[candidates[c].id] += scores[c];
  }
  return StepOutcome::Ok();
}

// The next run to make of `pending`: the plan's next, unless the looks ranked them (the sequence's
// next_run = "most_informative"), then the highest-ranked one some unit still takes.
std::size_t NextRun(SessionContext& ctx, const std::vector<int>& pending) {
  std::size_t best = 0;
  double best_score = 0.0;
  for (std::size_t i = 0; i < pending.size(); ++i) {
    const auto it = ctx.next_run_scores.find(pending[i]);
    if (it != ctx.next_run_scores.end() && it->second > best_score) {
      best = i;
      best_score = it->second;
    }
  }
  if (best != 0) {
    const SequenceRun& run =
        ctx.configs->sequence.runs[static_cast<std::size_t>(pending[best] - 1)];
    char line[160];
    std::snprintf(line, sizeof line,
                  "next: run %d (%.4g rad/s, %.4g s) before run %d: the most information for "
                  "the limits still undecided per second of table time",
                  pending[best], run.omega_rad_s, run.free_run_s, pending.front());
    ctx.Log(line);
  }
  ctx.next_run_scores.clear();
  return best;
}

// Estimates every complete run of the lane as recorded on disk (so the verdict is about exactly
// what the record holds), judges it against the limits, and closes the unit's session.
void EstimateAndClose(SessionContext& ctx, UnitLane& lane) {
  SessionResult& result = lane.result;
  result.dir = lane.dir;
  SessionOutcome outcome;
  const bool decided_at_interim_look = lane.decided != nullptr;
  LaneJudgement judged =
      decided_at_interim_look
          ? std::move(*lane.decided)
          : internal::JudgeLane(lane.dir, lane.ended_early.has_value(), ctx.configs->limits);
  lane.decided.reset();
  // A unit decided at an interim look closes with the verdict of the file's k on that estimate
  // (the interim k is larger: what it proved, the file's k proves too); any other judgement was
  // already the file's.
  if (decided_at_interim_look && judged.record && judged.judgement) {
    judged.judgement =
        JudgeRecordedSession(judged.estimate.method.summary, *judged.record, ctx.configs->limits);
  }
  result.complete_runs = judged.complete_runs;
  if (judged.error) {
    outcome.kind = OutcomeKind::kError;
    outcome.reason = *judged.error;
  } else {
    MethodResult& estimated = judged.estimate.method;
    std::vector<std::string> warnings = std::move(judged.estimate.warnings);
    result.estimate_json = std::move(judged.estimate.report);
    for (const std::string& w : estimated.summary.warnings) warnings.push_back(w);
    result.warnings.insert(result.warnings.end(), warnings.begin(), warnings.end());
    SessionJudgement& judgement = *judged.judgement;
    outcome = judgement.ToOutcome(result.estimate_json);
    result.verdict = std::move(judgement.verdict);
    result.engineering = std::move(judgement.engineering);
    result.estimate = std::move(estimated.summary);
    if (lane.ended_early) {
      outcome.ended_early = lane.ended_early;
      const std::string early =
          internal::DecidedWhen(*lane.ended_early) + " (" + lane.ended_early->why + ")";
      outcome.reason = outcome.reason.empty() ? early : outcome.reason + "; " + early;
    }
  }
  result.outcome = outcome.kind;
  result.reason = outcome.reason;
  if (auto closed = lane.recorder->Close(outcome); !closed) {
    result.outcome = OutcomeKind::kError;
    result.reason = "record: cannot close: " + closed.error().ToString();
  }
  result = Finish(std::move(result));
  lane.ended = true;
}

// The runs `ids` in order (each with the units that still need it), then each unit's estimate.
// A unit's own fault ends its lane and the others go on; a stop of the table's (a table fault, an
// interrupt) makes the hardware safe and closes every unit still in with the reason.
std::vector<SessionResult> RunPlanned(SessionContext& ctx, const std::vector<int>& ids,
                                      bool warm_up) {
  const SequenceConfig& seq = ctx.configs->sequence;
  ctx.run_count = static_cast<int>(ids.size());
  for (int id : ids)
    ctx.remaining_free_run_s += seq.runs[static_cast<std::size_t>(id - 1)].free_run_s;
  // The start's prompts come first: "mount the unit" is before the unit can warm up.
  StepOutcome step = internal::AskOperator(ctx, PromptPoint::kStart);
  if (step.ok() && warm_up) step = internal::WaitForWarmup(ctx);
  std::vector<int> pending = ids;
  for (int index = 1; !pending.empty() && step.ok() && ctx.LiveUnits() > 0; ++index) {
    const std::size_t next = NextRun(ctx, pending);
    const int id = pending[next];
    pending.erase(pending.begin() + static_cast<std::ptrdiff_t>(next));
    ctx.run_index = index;
    const SequenceRun& run = seq.runs[static_cast<std::size_t>(id - 1)];
    bool needed = false;
    for (const UnitLane& lane : ctx.lanes) needed = needed || lane.Takes(id);
    if (needed) {
      step = internal::AskOperator(ctx, PromptPoint::kBeforeRun, id);
      if (step.ok()) step = internal::RunOne(ctx, run, id);
      if (step.ok() && !pending.empty()) step = DecideEarly(ctx, id);
    } else {
      ctx.remaining_free_run_s = std::max(0.0, ctx.remaining_free_run_s - run.free_run_s);
    }
  }
  if (step.ok() && ctx.LiveUnits() > 0) step = internal::AskOperator(ctx, PromptPoint::kEnd);
  if (step.ok()) {
    if (ctx.LiveUnits() > 0) {
      // Normal end: bring the table to rest before the (long) estimates, the logs complete first.
      if (auto stopped = ctx.hw->table->Stop(); !stopped) ctx.hw->table->SafeStop();
      ctx.PumpCanLogs();
      Progress progress;
      progress.phase = "estimate";
      ctx.ReportProgress(progress, true);
      for (UnitLane& lane : ctx.lanes) {
        if (!lane.ended) EstimateAndClose(ctx, lane);
      }
    }
  } else {
    internal::MakeSafe(*ctx.hw);
    for (UnitLane& lane : ctx.lanes) {
      if (!lane.ended) ctx.CloseStopped(lane, step, "table commanded to zero rate, gyro stopped");
    }
    internal::WatchTableStop(ctx);
  }
  std::vector<SessionResult> results;
  for (UnitLane& lane : ctx.lanes) results.push_back(std::move(lane.result));
  return results;
}

void Begin(SessionContext& ctx, const BenchConfigs& configs, const BenchHardware& hw,
           const RunnerOptions& options) {
  ctx.configs = &configs;
  ctx.hw = &hw;
  ctx.options = &options;
  ctx.earth_rate_rad_s = EarthRateOnAxisRadS(configs.station.site);
  ctx.start_ns = hw.clock->NowNs();
  const std::int64_t unix_now = std::chrono::duration_cast<std::chrono::nanoseconds>(
                                    std::chrono::system_clock::now().time_since_epoch())
                                    .count();
  ctx.unix_offset_ns = unix_now - ctx.start_ns;
  // The interim looks' k, once for the session: an integration over every look the plan has
  // (analysis/interim_looks.hpp), or the sequence's own.
  const AdaptiveStop& adaptive = configs.sequence.adaptive;
  ctx.interim_limits = configs.limits;
  if (adaptive.stop_when_decided) {
    ctx.interim_limits.decision.coverage_factor =
        adaptive.interim_coverage_factor.value_or(InterimCoverageFactor(
            configs.limits.decision.coverage_factor, configs.sequence.InterimLookFractions()));
  }
  ctx.looks = std::make_unique<internal::LookWorker>(*hw.clock);
}

// The lanes' labels: none for a session of one unit (its log reads as before), "A SN-1: " else.
void LabelLanes(SessionContext& ctx, const std::vector<UnitSession>& units) {
  if (ctx.lanes.size() < 2) return;
  for (std::size_t i = 0; i < ctx.lanes.size(); ++i)
    ctx.lanes[i].label = ctx.hw->units[i].position + " " + units[i].serial + ": ";
}

// What the capture thread will get, asked of the system before the session starts, so the record
// says what was granted and, where refused, why: memory is locked for the process here (as the
// capture would), scheduling and affinity are tried on a probe thread exactly as the capture thread
// applies them.
std::string ProbeRealtime(const RealtimeConfig& rt) {
  const RealtimeOptions options{rt.priority, rt.cpu, rt.lock_memory};
  if (options.priority == 0 && options.cpu < 0 && !options.lock_memory) return "not requested";
  RealtimeReport report;
  if (options.lock_memory) report.memory_lock = LockProcessMemory();
  std::thread probe([&] { realtime_internal::ApplyToCallingThread(options, report); });
  probe.join();
  return report.Summary();
}

// The sequencer owns the table and feeds its watchdog: on a simulated clock, time must wait for
// this thread from the session's first moment, not from its first sleep (else a capture or
// monitor thread's waits let time run on while it writes files, and the watchdog expires).
class ClockAttachment {
 public:
  explicit ClockAttachment(hw::Clock& clock) : clock_(clock) { clock_.AttachCurrentThread(); }
  ~ClockAttachment() { clock_.DetachCurrentThread(); }
  ClockAttachment(const ClockAttachment&) = delete;
  ClockAttachment& operator=(const ClockAttachment&) = delete;

 private:
  hw::Clock& clock_;
};

SessionResult Refused(const std::filesystem::path& dir, std::string reason) {
  SessionResult result;
  result.dir = dir;
  result.outcome = OutcomeKind::kError;
  result.reason = std::move(reason);
  return Finish(std::move(result));
}

// Every unit refused with the same reason, the hardware made safe; nothing was run.
std::vector<SessionResult> RefuseAll(const BenchHardware& hw, const std::vector<UnitSession>& units,
                                     const std::string& reason) {
  internal::MakeSafe(hw);
  std::vector<SessionResult> results;
  for (const UnitSession& unit : units) results.push_back(Refused(unit.dir, reason));
  return results;
}

std::optional<std::string> StartProblem(const BenchConfigs& configs, const BenchHardware& hw,
                                        const std::vector<UnitSession>& units,
                                        const RunnerOptions& options) {
  if (hw.units.empty()) return "no unit on the table";
  // Refused before anything moves: the first prompt would otherwise stop a running session.
  if (!configs.sequence.prompts.empty() && options.prompts == nullptr)
    return configs.sequence.file.string() + ": " + std::to_string(configs.sequence.prompts.size()) +
           " operator prompt(s) ([[prompts]]) and nothing to answer them";
  if (units.size() != hw.units.size())
    return std::to_string(units.size()) + " unit session(s) for " +
           std::to_string(hw.units.size()) + " fitted position(s)";
  return std::nullopt;
}

// What unit i's session.json starts with, and the config copies written before it.
std::expected<SessionHeader, std::string> UnitHeader(const BenchConfigs& configs,
                                                     const BenchHardware& hw,
                                                     const std::vector<UnitSession>& units,
                                                     std::size_t i, const RunnerOptions& options,
                                                     const std::string& realtime_status) {
  SessionHeader header;
  header.unit_serial = units[i].serial;
  header.station_name = configs.station.name;
  header.operator_name = options.operator_name;
  header.software_version = options.software_version;
  header.config_sha256 = {configs.station.sha256_hex, configs.sequence.sha256_hex,
                          configs.limits.sha256_hex};
  header.realtime_status = realtime_status;
  header.simulation = units[i].simulation;
  header.electronics = nlohmann::json{
      {session::keys::kOutputFilter, OutputFilterJson(configs.station.gyro.output_filter)},
      {session::keys::kPickoff, PickoffDeclarationJson(configs.station.gyro.pickoff)},
      {session::keys::kIqConvention,
       std::string(estimator::IqConventionName(configs.station.gyro.iq_convention))}};
  header.can_interface = hw.units[i].can_interface;
  header.can_node = hw.units[i].can_node;
  header.can_protocol = hw.units[i].can_protocol;
  header.fixture = units[i].fixture;
  // The plan in the unit's own frame: an inverted unit is commanded −Ω.
  const double sign = hw.units[i].axis_sign;
  int id = 1;
  for (const SequenceRun& run : configs.sequence.runs)
    header.runs.push_back({id++, sign * run.omega_rad_s, run.a, run.b, run.theta_rad,
                           run.free_run_s, static_cast<double>(run.sample_rate_hz)});
  auto copies = internal::ConfigCopies(configs);
  if (!copies) return std::unexpected(copies.error());
  header.files_first = std::move(*copies);
  return header;
}

// A unit folder a kill left before its session.json was written holds only what Create writes
// first (empty runs/ and can/session.log, config/, session.json's temporary): nothing was run, so
// it may start afresh.
// Anything else in it is not ours to remove; the reason says what is there.
std::optional<std::string> ClearUnstartedFolder(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(dir, ec)) return std::nullopt;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    // session.json's temporary (session::WriteFileAtomic) when the kill came before its rename.
    const bool temporary = name.rfind(".session.json.tmp.", 0) == 0;
    if (temporary) {
      fs::remove(entry.path(), ec);
      continue;
    }
    const bool create_made = name == "config" || name == "runs" || name == "can";
    if (!create_made)
      return entry.path().string() + ": not written by a session that had started; the folder " +
             "has no session.json (remove what is not yours, then resume again)";
    if (name == "runs" && !fs::is_empty(entry.path(), ec))
      return entry.path().string() + ": holds run files but the folder has no session.json";
  }
  for (const char* made : {"config", "runs", "can"}) fs::remove_all(dir / made, ec);
  if (ec) return dir.string() + ": cannot clear the unstarted folder: " + ec.message();
  return std::nullopt;
}

}  // namespace

std::vector<SessionResult> RunSessions(const BenchConfigs& configs, const BenchHardware& hw,
                                       const std::vector<UnitSession>& units,
                                       const RunnerOptions& options) {
  if (auto problem = StartProblem(configs, hw, units, options))
    return RefuseAll(hw, units, *problem);
  const ClockAttachment attached(*hw.clock);
  const std::string realtime_status = ProbeRealtime(configs.station.realtime);
  std::vector<SessionRecorder> recorders;
  recorders.reserve(units.size());
  for (std::size_t i = 0; i < units.size(); ++i) {
    auto header = UnitHeader(configs, hw, units, i, options, realtime_status);
    std::string problem;
    if (!header) {
      problem = "record: " + header.error();
    } else if (auto recorder = SessionRecorder::Create(units[i].dir, *header); !recorder) {
      problem = "record: " + recorder.error().ToString();
    } else {
      recorders.push_back(std::move(*recorder));
    }
    // A unit whose record cannot be made runs nothing; nor, then, does the table: a session
    // starts with every record in place or not at all.
    if (!problem.empty()) {
      const std::string reason = "record of " + units[i].serial + ": " + problem;
      for (SessionRecorder& made : recorders) {
        (void)made.Close(SessionOutcome{
            OutcomeKind::kError, reason, {}, std::nullopt, std::nullopt, std::nullopt});
      }
      std::vector<SessionResult> results = RefuseAll(hw, units, reason);
      results[i].reason = problem;
      return results;
    }
  }
  SessionContext ctx;
  Begin(ctx, configs, hw, options);
  for (std::size_t i = 0; i < units.size(); ++i) {
    UnitLane lane;
    lane.hw = &hw.units[i];
    lane.recorder = &recorders[i];
    lane.dir = units[i].dir;
    for (const RecordedRun& run : recorders[i].Runs()) lane.remaining.insert(run.plan.id);
    ctx.lanes.push_back(std::move(lane));
  }
  LabelLanes(ctx, units);
  std::vector<int> ids;
  for (const RecordedRun& run : recorders.front().Runs()) ids.push_back(run.plan.id);
  return RunPlanned(ctx, ids, /*warm_up=*/true);
}

std::vector<SessionResult> ResumeSessions(const BenchConfigs& configs, const BenchHardware& hw,
                                          const std::vector<UnitSession>& units,
                                          const RunnerOptions& options) {
  if (auto problem = StartProblem(configs, hw, units, options))
    return RefuseAll(hw, units, *problem);
  const ClockAttachment attached(*hw.clock);
  std::vector<SessionRecorder> recorders;
  recorders.reserve(units.size());
  std::optional<std::string> realtime_status;
  for (std::size_t i = 0; i < units.size(); ++i) {
    const UnitSession& unit = units[i];
    std::error_code ec;
    if (!std::filesystem::exists(unit.dir / "session.json", ec)) {
      // Killed before this unit's record was written (a fixture's other units may have started):
      // nothing of it was run, so it starts afresh with every run to do.
      if (!realtime_status) realtime_status = ProbeRealtime(configs.station.realtime);
      auto header = UnitHeader(configs, hw, units, i, options, *realtime_status);
      if (!header) return RefuseAll(hw, units, "record of " + unit.serial + ": " + header.error());
      if (auto cleared = ClearUnstartedFolder(unit.dir))
        return RefuseAll(hw, units, "record of " + unit.serial + ": " + *cleared);
      auto created = SessionRecorder::Create(unit.dir, *header);
      if (!created)
        return RefuseAll(hw, units, "record of " + unit.serial + ": " + created.error().ToString());
      recorders.push_back(std::move(*created));
      continue;
    }
    auto recorder = SessionRecorder::OpenForResume(unit.dir, {}, options.operator_name);
    if (!recorder) {
      // The others stay as they were (they read as interrupted, and resume again).
      std::vector<SessionResult> results = RefuseAll(
          hw, units, "record of " + unit.dir.string() + ": " + recorder.error().ToString());
      return results;
    }
    recorders.push_back(std::move(*recorder));
  }
  SessionContext ctx;
  Begin(ctx, configs, hw, options);
  std::set<int> all;
  for (std::size_t i = 0; i < units.size(); ++i) {
    UnitLane lane;
    lane.hw = &hw.units[i];
    lane.recorder = &recorders[i];
    lane.dir = units[i].dir;
    for (int id : recorders[i].RemainingRunIds()) {
      if (id < 1 || static_cast<std::size_t>(id) > configs.sequence.runs.size())
        return RefuseAll(hw, units,
                         units[i].dir.string() + ": session plans run " + std::to_string(id) +
                             ", which the saved sequence does not have");
      lane.remaining.insert(id);
      all.insert(id);
    }
    ctx.lanes.push_back(std::move(lane));
  }
  LabelLanes(ctx, units);
  const std::vector<int> ids(all.begin(), all.end());
  for (const UnitLane& lane : ctx.lanes)
    ctx.Log(lane, "resuming " + lane.dir.string() + ": " + std::to_string(lane.remaining.size()) +
                      " run(s) to go");
  // Warm-up again: the gyros may have cooled since the session stopped.
  return RunPlanned(ctx, ids, /*warm_up=*/!ids.empty());
}

SessionResult RunSession(const BenchConfigs& configs, const BenchHardware& hw,
                         const std::filesystem::path& dir, const RunnerOptions& options) {
  const std::vector<UnitSession> unit{{options.unit_serial, dir, options.simulation, std::nullopt}};
  return RunSessions(configs, hw, unit, options).front();
}

SessionResult ResumeSession(const BenchConfigs& configs, const BenchHardware& hw,
                            const std::filesystem::path& dir, const RunnerOptions& options) {
  const std::vector<UnitSession> unit{{options.unit_serial, dir, std::nullopt, std::nullopt}};
  return ResumeSessions(configs, hw, unit, options).front();
}

}  // namespace hrgbench::bench
