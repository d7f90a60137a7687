#include "hrgbench/bench/sequencer/sequencer.hpp"

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <expected>
#include <optional>
#include <set>
#include <thread>

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

}  // namespace internal

namespace {

using internal::SessionContext;
using internal::StepOutcome;
using internal::StopKind;
using internal::UnitLane;

SessionResult Finish(SessionResult result) {
  result.exit_code = ExitCode(result.outcome);
  return result;
}

}  // namespace

// A unit's complete runs as recorded on disk, estimated and judged against the limits: what its
// session closes with, and (the sequence's [adaptive]) what it would close with now.
struct internal::LaneJudgement {
  std::optional<std::string> error;  // the record cannot be read back, or has no complete run
  int complete_runs = 0;
  RecordedEstimate estimate;
  std::optional<session::SessionRecord> record;  // what the estimate was judged with
  std::optional<SessionJudgement> judgement;
};

namespace {

using internal::LaneJudgement;

// `plan_cut_short`: runs still planned are not a defect of the record (the unit ended early, or
// the session is still going). Judged against `limits` (the file's, or an interim look's).
LaneJudgement JudgeLane(const UnitLane& lane, bool plan_cut_short, const LimitsConfig& limits) {
  LaneJudgement out;
  session::ReadOptions read;
  read.min_samples_per_run = MinimumSamples(Method::kMl);
  read.extra_columns = false;  // the estimate reads t_s and y only
  read.plan_cut_short = plan_cut_short;
  auto recorded = session::ReadSession(lane.dir, read);
  // The same document typed by the record's one reader (no second read of the file).
  std::expected<session::SessionRecord, session::SessionError> record =
      recorded ? session::ReadSessionRecord(recorded->document, lane.dir / "session.json")
               : std::unexpected(recorded.error());
  if (!record) {
    out.error = "the record cannot be read back: " + record.error().ToString();
    return out;
  }
  out.complete_runs = static_cast<int>(recorded->loaded_samples.size());
  if (recorded->loaded_samples.empty()) {
    out.error = "no complete run to estimate from";
    return out;
  }
  out.estimate = EstimateRecordedSession(std::move(*recorded), *record, limits.fit);
  out.judgement = JudgeRecordedSession(out.estimate.method.summary, *record, limits);
  out.record = std::move(*record);
  return out;
}

// Why a verdict can no longer change with more runs, or nothing: every δ and ξ estimated (none
// held: an estimate conditional on a held value has a std that leaves out the held value's error,
// and after one run of the production sequence it "proved" δ4 of a good unit out of its limits),
// the fit acceptable on the runs so far, and a limit proven non-conforming (the unit fails
// whatever else), or every limit proven conforming or not. An undecided limit (inside a guard
// band), a limit not yet evaluable, a misfit or no limits at all: more runs may change it.
std::optional<std::string> DecidedWhy(const estimator::EstimateSummary& estimate,
                                      const std::optional<Verdict>& verdict) {
  if (!verdict || !verdict->fit_acceptable || verdict->results.empty()) return std::nullopt;
  for (const bool estimated : estimate.delta_estimated)
    if (!estimated) return std::nullopt;
  for (const bool estimated : estimate.xi_estimated)
    if (!estimated) return std::nullopt;
  for (const LimitResult& r : verdict->results) {
    if (r.zone == DecisionZone::kNonConforming)
      return std::string(ToString(r.quantity)) + " proven non-conforming";
  }
  for (const LimitResult& r : verdict->results) {
    if (r.status == LimitStatus::kNotEvaluated || r.zone == DecisionZone::kUndecided)
      return std::nullopt;
  }
  return std::string("every limit decided");
}

// The sequence's [adaptive], after run `run_id`: each unit still measuring whose verdict can no
// longer change takes no further run (RunPlanned then skips the runs nobody needs). An interim
// look decides with the interim coverage factor (analysis/interim_looks.hpp), never the file's k.
void DecideEarly(SessionContext& ctx, int run_id) {
  const AdaptiveStop& adaptive = ctx.configs->sequence.adaptive;
  if (!adaptive.stop_when_decided) return;
  const int planned = static_cast<int>(ctx.configs->sequence.runs.size());
  LimitsConfig interim = ctx.configs->limits;
  interim.decision.coverage_factor = adaptive.interim_coverage_factor.value_or(
      InterimCoverageFactor(interim.decision.coverage_factor, planned - adaptive.min_runs));
  char k_text[48];
  std::snprintf(k_text, sizeof k_text, "interim k = %.3g", interim.decision.coverage_factor);
  for (UnitLane& lane : ctx.lanes) {
    if (lane.ended || lane.remaining.empty()) continue;
    LaneJudgement now = JudgeLane(lane, /*plan_cut_short=*/true, interim);
    if (now.error || now.complete_runs < adaptive.min_runs || !now.judgement) continue;
    const std::optional<std::string> why =
        DecidedWhy(now.estimate.method.summary, now.judgement->verdict);
    if (!why) {
      ctx.Log(lane, "after run " + std::to_string(run_id) + ": not decided yet at " + k_text +
                        " (" + now.judgement->reason + ")");
      continue;
    }
    lane.ended_early = EarlyEnd{run_id, planned, *why, interim.decision.coverage_factor};
    if (ctx.options->on_decided)
      ctx.options->on_decided(static_cast<std::size_t>(&lane - ctx.lanes.data()),
                              *lane.ended_early);
    ctx.Log(lane, "decided after run " + std::to_string(run_id) + " of " + std::to_string(planned) +
                      " (" + *why + ", " + k_text + "): " + std::to_string(lane.remaining.size()) +
                      " planned run(s) not needed");
    lane.remaining.clear();
    lane.decided = std::make_shared<LaneJudgement>(std::move(now));
  }
}

// Estimates every complete run of the lane as recorded on disk (so the verdict is about exactly
// what the record holds), judges it against the limits, and closes the unit's session.
void EstimateAndClose(SessionContext& ctx, UnitLane& lane) {
  SessionResult& result = lane.result;
  result.dir = lane.dir;
  SessionOutcome outcome;
  const bool decided_at_interim_look = lane.decided != nullptr;
  LaneJudgement judged = decided_at_interim_look
                             ? std::move(*lane.decided)
                             : JudgeLane(lane, lane.ended_early.has_value(), ctx.configs->limits);
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
      const std::string early = "decided after run " + std::to_string(lane.ended_early->after_run) +
                                " of " + std::to_string(lane.ended_early->planned_runs) + " (" +
                                lane.ended_early->why + ")";
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
  for (std::size_t i = 0; i < ids.size() && step.ok() && ctx.LiveUnits() > 0; ++i) {
    ctx.run_index = static_cast<int>(i) + 1;
    const SequenceRun& run = seq.runs[static_cast<std::size_t>(ids[i] - 1)];
    bool needed = false;
    for (const UnitLane& lane : ctx.lanes) needed = needed || lane.Takes(ids[i]);
    if (needed) {
      step = internal::AskOperator(ctx, PromptPoint::kBeforeRun, ids[i]);
      if (step.ok()) step = internal::RunOne(ctx, run, ids[i]);
      if (step.ok() && i + 1 < ids.size()) DecideEarly(ctx, ids[i]);
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
