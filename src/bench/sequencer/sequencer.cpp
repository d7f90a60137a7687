#include "hrgbench/bench/sequencer.hpp"

#include <chrono>
#include <cmath>
#include <csignal>
#include <thread>

#include "bench/sequencer/run_context.hpp"
#include "bench/sequencer/saved_configs.hpp"
#include "hrgbench/bench/realtime_setup.hpp"
#include "hrgbench/bench/recorded_estimate.hpp"
#include "hrgbench/bench/recorded_frequency.hpp"
#include "hrgbench/bench/verdict_json.hpp"
#include "hrgbench/session/session.hpp"

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
  // Outside a capture the free-run time still ahead is the estimate (the capture knows better).
  if (p.phase != "capture") p.remaining_s = remaining_free_run_s;
  options->on_progress(p);
}

double SessionContext::Seconds(std::int64_t from_ns) const {
  return static_cast<double>(from_ns - start_ns) * 1e-9;
}

StepOutcome SessionContext::PumpCanLog() {
  if (hw->monitor == nullptr) return StepOutcome::Ok();
  logged_scratch.clear();
  hw::CanFrame frame;
  hw::ReceiveInfo info;
  // Bounded: a babbling bus must not keep the sequencer from its other duties.
  for (int i = 0; i < 100000; ++i) {
    if (hw->monitor->Receive(&frame, 0, &info) != hw::CanStatus::kOk) break;
    std::int64_t unix_ns = hw->clock->NowNs() + unix_offset_ns;
    if (info.timestamp_ns != 0) {
      if (hw->monitor_stamps_on_bench_clock)
        unix_ns = info.timestamp_ns + unix_offset_ns;
      else if (info.timestamp_source == hw::TimestampSource::kSoftware)
        unix_ns = info.timestamp_ns;  // already CLOCK_REALTIME
    }
    logged_scratch.push_back({unix_ns, frame});
  }
  if (logged_scratch.empty()) return StepOutcome::Ok();
  if (auto appended = recorder->AppendCanFrames(logged_scratch); !appended)
    return StepOutcome::Error("record: CAN log: " + appended.error().ToString());
  return StepOutcome::Ok();
}

void MakeSafe(const BenchHardware& hw) noexcept {
  hw.table->SafeStop();
  try {
    (void)hw.gyro->Stop();
  } catch (...) {
    // Only std::bad_alloc can get here; the table is already safe.
  }
}

}  // namespace internal

namespace {

using internal::SessionContext;
using internal::StepOutcome;
using internal::StopKind;

SessionResult Finish(SessionResult result) {
  result.exit_code = ExitCode(result.outcome);
  return result;
}

// Estimates every complete run as recorded on disk (so the verdict is about exactly what the record
// holds), judges it against the limits, and closes the session.
SessionResult EstimateAndClose(SessionContext& ctx, const std::filesystem::path& dir,
                               SessionResult result) {
  Progress progress;
  progress.phase = "estimate";
  ctx.ReportProgress(progress, true);
  SessionOutcome outcome;
  session::ReadOptions read;
  read.min_samples_per_run = MinimumSamples(Method::kMl);
  auto recorded = session::ReadSession(dir, read);
  if (!recorded) {
    outcome.kind = OutcomeKind::kError;
    outcome.reason = "the record cannot be read back: " + recorded.error().ToString();
  } else {
    result.complete_runs = static_cast<int>(recorded->loaded_samples.size());
    if (recorded->loaded_samples.empty()) {
      outcome.kind = OutcomeKind::kError;
      outcome.reason = "no complete run to estimate from";
    } else {
      RecordedEstimate recorded_estimate =
          EstimateRecordedSession(*recorded, ctx.configs->limits.fit);
      MethodResult& estimated = recorded_estimate.method;
      std::vector<std::string> warnings = std::move(recorded_estimate.warnings);
      result.estimate_json = std::move(recorded_estimate.report);
      outcome.estimate = result.estimate_json;
      for (const std::string& w : estimated.summary.warnings) warnings.push_back(w);
      result.warnings.insert(result.warnings.end(), warnings.begin(), warnings.end());
      if (!estimated.summary.IsUsable()) {
        outcome.kind = OutcomeKind::kError;
        outcome.reason = "estimate not usable: " + estimated.summary.message;
      } else {
        const estimator::EngineeringQuantities engineering =
            estimator::ComputeEngineeringQuantities(
                estimated.summary, RecordedResonantFrequency(recorded->document).hz);
        Verdict verdict = EvaluateLimits(ctx.configs->limits, estimated.summary, engineering);
        outcome.verdict = VerdictJson(verdict);
        std::string not_judged;  // "xi2: not evaluated, held fixed ...; delta4: ..."
        for (const LimitResult& r : verdict.results) {
          if (r.status == LimitStatus::kFail)
            outcome.failed_parameters.push_back(
                {std::string(ToString(r.quantity)), r.value, r.min, r.max});
          if (r.status == LimitStatus::kNotEvaluated)
            not_judged += (not_judged.empty() ? "" : "; ") + r.message;
        }
        std::string names;
        for (const FailedParameter& f : outcome.failed_parameters)
          names += (names.empty() ? "" : ", ") + f.name;
        // PASS means every declared limit was judged and met. A limit the bench could not judge
        // (the information was rank-deficient at run time, say) is the bench's failure: ERROR.
        // A limit that failed is the unit's, whatever else could not be judged: FAIL.
        switch (verdict.overall) {
          case LimitStatus::kFail:
            outcome.kind = OutcomeKind::kFail;
            outcome.reason = "out of limits: " + names;
            if (!not_judged.empty()) outcome.reason += "; not judged: " + not_judged;
            break;
          case LimitStatus::kNotEvaluated:
            outcome.kind = OutcomeKind::kError;
            outcome.reason =
                verdict.fit_acceptable
                    ? "limits not judged: " + not_judged
                    : "the fit is outside its model, no limit judged: " + verdict.FitProblems();
            break;
          case LimitStatus::kPass:
            outcome.kind = OutcomeKind::kPass;
            outcome.reason = ctx.configs->limits.limits.empty()
                                 ? "the fit is within its model; no limits to judge"
                                 : "the fit is within its model and every limit met";
            break;
        }
        result.verdict = std::move(verdict);
        result.engineering = engineering;
      }
      result.estimate = std::move(estimated.summary);
    }
  }
  result.outcome = outcome.kind;
  result.reason = outcome.reason;
  if (auto closed = ctx.recorder->Close(outcome); !closed) {
    result.outcome = OutcomeKind::kError;
    result.reason = "record: cannot close: " + closed.error().ToString();
  }
  return Finish(std::move(result));
}

// The runs `ids` in order, then the estimate; any stop makes the hardware safe and closes the
// session with the reason.
SessionResult RunPlanned(SessionContext& ctx, const std::filesystem::path& dir,
                         const std::vector<int>& ids, bool warm_up) {
  SessionResult result;
  result.dir = dir;
  const SequenceConfig& seq = ctx.configs->sequence;
  ctx.run_count = static_cast<int>(ids.size());
  for (int id : ids)
    ctx.remaining_free_run_s += seq.runs[static_cast<std::size_t>(id - 1)].free_run_s;
  StepOutcome step = warm_up ? internal::WaitForWarmup(ctx) : StepOutcome::Ok();
  for (std::size_t i = 0; i < ids.size() && step.ok(); ++i) {
    ctx.run_index = static_cast<int>(i) + 1;
    step = internal::RunOne(ctx, seq.runs[static_cast<std::size_t>(ids[i] - 1)], ids[i]);
  }
  result.warnings = ctx.warnings;
  if (step.ok()) {
    // Normal end: bring the table to rest before the (long) estimate, the log complete first.
    if (auto stopped = ctx.hw->table->Stop(); !stopped) ctx.hw->table->SafeStop();
    step = ctx.PumpCanLog();
    if (step.ok()) return EstimateAndClose(ctx, dir, std::move(result));
  }
  internal::MakeSafe(*ctx.hw);
  // The safe-state commands and whatever came before them, in the log before it closes; a log
  // that cannot be written now changes nothing (the session already stops with its reason).
  (void)ctx.PumpCanLog();
  ctx.Log("stopping: " + step.reason + "; table commanded to zero rate, gyro stopped");
  SessionOutcome outcome;
  outcome.kind = step.stop == StopKind::kAborted ? OutcomeKind::kAborted : OutcomeKind::kError;
  outcome.reason = step.reason;
  result.outcome = outcome.kind;
  result.reason = step.reason;
  if (auto closed = ctx.recorder->Close(outcome); !closed)
    result.reason += "; record: cannot close: " + closed.error().ToString();
  return Finish(std::move(result));
}

void Begin(SessionContext& ctx, const BenchConfigs& configs, const BenchHardware& hw,
           const RunnerOptions& options, SessionRecorder* recorder) {
  ctx.configs = &configs;
  ctx.hw = &hw;
  ctx.options = &options;
  ctx.recorder = recorder;
  ctx.earth_rate_rad_s = EarthRateOnAxisRadS(configs.station.site);
  ctx.start_ns = hw.clock->NowNs();
  const std::int64_t unix_now = std::chrono::duration_cast<std::chrono::nanoseconds>(
                                    std::chrono::system_clock::now().time_since_epoch())
                                    .count();
  ctx.unix_offset_ns = unix_now - ctx.start_ns;
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

}  // namespace

SessionResult RunSession(const BenchConfigs& configs, const BenchHardware& hw,
                         const std::filesystem::path& dir, const RunnerOptions& options) {
  const ClockAttachment attached(*hw.clock);
  SessionHeader header;
  header.unit_serial = options.unit_serial;
  header.station_name = configs.station.name;
  header.software_version = options.software_version;
  header.config_sha256 = {configs.station.sha256_hex, configs.sequence.sha256_hex,
                          configs.limits.sha256_hex};
  header.realtime_status = ProbeRealtime(configs.station.realtime);
  header.simulation = options.simulation;
  header.electronics =
      nlohmann::json{{"output_filter", OutputFilterJson(configs.station.gyro.output_filter)}};
  header.can_interface = hw.can_interface;
  int id = 1;
  for (const SequenceRun& run : configs.sequence.runs)
    header.runs.push_back({id++, run.omega_rad_s, run.a, run.b, run.theta_rad, run.free_run_s,
                           static_cast<double>(run.sample_rate_hz)});
  auto recorder = SessionRecorder::Create(dir, header);
  if (!recorder) {
    internal::MakeSafe(hw);
    return Refused(dir, "record: " + recorder.error().ToString());
  }
  if (auto saved = internal::SaveConfigs(configs, dir); !saved) {
    SessionOutcome outcome{
        OutcomeKind::kError, "record: " + saved.error(), {}, std::nullopt, std::nullopt};
    (void)recorder->Close(outcome);
    internal::MakeSafe(hw);
    return Refused(dir, outcome.reason);
  }
  SessionContext ctx;
  Begin(ctx, configs, hw, options, &*recorder);
  std::vector<int> ids;
  for (const RecordedRun& run : recorder->Runs()) ids.push_back(run.plan.id);
  return RunPlanned(ctx, dir, ids, /*warm_up=*/true);
}

SessionResult ResumeSession(const BenchConfigs& configs, const BenchHardware& hw,
                            const std::filesystem::path& dir, const RunnerOptions& options) {
  const ClockAttachment attached(*hw.clock);
  auto recorder = SessionRecorder::OpenForResume(dir);
  if (!recorder) {
    internal::MakeSafe(hw);
    return Refused(dir, "record: " + recorder.error().ToString());
  }
  SessionContext ctx;
  Begin(ctx, configs, hw, options, &*recorder);
  const std::vector<int> ids = recorder->RemainingRunIds();
  for (int id : ids) {
    if (id < 1 || static_cast<std::size_t>(id) > configs.sequence.runs.size())
      return Refused(dir, "session plans run " + std::to_string(id) +
                              ", which the saved sequence does not have");
  }
  ctx.Log("resuming " + dir.string() + ": " + std::to_string(ids.size()) + " run(s) to go");
  // Warm-up again: the gyro may have cooled since the session stopped.
  return RunPlanned(ctx, dir, ids, /*warm_up=*/!ids.empty());
}

}  // namespace hrgbench::bench
