// One free run: table to Ω, settle, excite, ready, release, capture, stop, judge, record; every
// unit that still needs the run takes part.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <expected>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "bench/sequencer/interim_look.hpp"
#include "bench/sequencer/run_context.hpp"
#include "bench/sequencer/run_omega_readings.hpp"
#include "bench/sequencer/table_settle.hpp"
#include "hrgbench/analysis/run_acceptance.hpp"

namespace hrgbench::bench::internal {
namespace {

constexpr std::int64_t kNsPerS = 1'000'000'000;
// How often the run loop drains the ring, reads the table and reports progress (hardware clock).
constexpr std::int64_t kLoopPeriodNs = 20'000'000;
constexpr std::int64_t kTableReadPeriodNs = 20'000'000;
// The wait for "ready" is cut into slices this long, the table's heartbeat sent between them:
// well inside any heartbeat period the station allows.
constexpr std::int64_t kReadySliceNs = 50'000'000;

using hw::SecondsToNs;

std::string Format(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

// Table to rate and settled, with interrupts seen between slices.
StepOutcome SettleTable(SessionContext& ctx, double omega_rad_s) {
  const SequenceConfig& seq = ctx.configs->sequence;
  if (auto set = ctx.hw->table->SetRate(omega_rad_s); !set)
    return StepOutcome::Error("rate table: cannot command " + Format("%g", omega_rad_s) +
                              " rad/s: " + set.error().ToString());
  hw::StableCriteria criteria;
  criteria.tolerance_rad_s = seq.settle.rate_tolerance_rad_s;
  criteria.dwell_s = seq.settle.dwell_s;
  criteria.poll_period_s = seq.settle.poll_period_s;
  const TableSettleResult settled = WaitTableSettled(
      *ctx.hw->table, *ctx.hw->clock, criteria, seq.timeouts.settle_s,
      [&ctx] { return ctx.Interrupted(); }, [&ctx] { ctx.PumpCanLogs(); });
  switch (settled.end) {
    case TableSettle::kStable:
      return StepOutcome::Ok();
    case TableSettle::kStopped:
      return StepOutcome::Aborted(ctx.InterruptCause() + " while the table settled");
    case TableSettle::kTimedOut:
      return StepOutcome::Error("rate table not stable at " + Format("%g", omega_rad_s) +
                                " rad/s within " + Format("%g", seq.timeouts.settle_s) + " s");
    case TableSettle::kTableError:
      break;
  }
  return StepOutcome::Error("rate table: " + settled.table_error);
}

// Gyro configured and excited (the wait for "ready" comes after every unit is excited).
StepOutcome ExciteGyro(hw::GyroElectronics& gyro, const SequenceRun& run) {
  if (gyro.State() != hw::GyroMode::kConfigured && gyro.State() != hw::GyroMode::kReady) {
    if (auto configured = gyro.Configure({.sample_rate_hz = run.sample_rate_hz}); !configured)
      return StepOutcome::Error("gyro: configure: " + configured.error().ToString());
  }
  if (auto excited = gyro.Excite({run.a, run.b, run.theta_rad}); !excited)
    return StepOutcome::Error("gyro: excite: " + excited.error().ToString());
  return StepOutcome::Ok();
}

// Why a unit did not become ready: its own fault (its lane ends), or the table's stop (an
// interrupt, the table's link: every unit's).
struct NotReady {
  StepOutcome outcome;
  bool table = false;
};

// Waits until the lane's gyro reports ready or `deadline` passes.
std::expected<hw::GyroStatus, NotReady> WaitUntilReady(SessionContext& ctx, UnitLane& lane,
                                                       std::int64_t deadline) {
  for (;;) {
    if (ctx.Interrupted())
      return std::unexpected(
          NotReady{StepOutcome::Aborted(ctx.InterruptCause() + " during excitation"), true});
    // Asked at least once, however late: the units are waited for in turn, and one that became
    // ready while another was waited for is ready, whatever the deadline says by now.
    const std::int64_t left = std::max<std::int64_t>(0, deadline - ctx.hw->clock->NowNs());
    // The table turns meanwhile: its watchdog is fed between slices (a unit's excitation may
    // take longer than the watchdog's timeout, and so may the wait for several units).
    auto ready = lane.hw->gyro->WaitReady(std::min(left, kReadySliceNs));
    if (auto fed = ctx.hw->table->Heartbeat(); !fed)
      return std::unexpected(
          NotReady{StepOutcome::Error("rate table: " + fed.error().ToString()), true});
    ctx.PumpCanLogs();
    if (lane.ended) return std::unexpected(NotReady{StepOutcome::Error(lane.result.reason)});
    if (ready) return *ready;
    if (ready.error().code == hw::GyroErrorCode::kTimeout && left == 0)
      return std::unexpected(NotReady{
          StepOutcome::Error("gyro not ready within " +
                             Format("%g", ctx.configs->sequence.timeouts.excite_s) + " s")});
    if (ready.error().code != hw::GyroErrorCode::kTimeout)
      return std::unexpected(NotReady{StepOutcome::Error("gyro: " + ready.error().ToString())});
  }
}

// One unit's part of a run: from its release to its end in the record.
struct UnitRun {
  UnitLane* lane = nullptr;
  RunStart start;
  std::int64_t release_stamp_ns = 0;  // the acknowledged release, transport time base
  std::int64_t released_at_ns = 0;    // the same on the bench clock (deadlines, progress)
  bool begun = false;                 // BeginRun recorded: EndRun must follow
  std::unique_ptr<SampleRing> ring;
  std::unique_ptr<CaptureThread> capture;
  StepOutcome outcome;  // the unit's own fault in this run
  std::uint64_t samples = 0;
  // The electronics' last reported conditions (the status at ready, then each sample's): what a
  // sample its electronics did not stamp is recorded with, so the run's columns stay complete.
  double temperature_c = std::numeric_limits<double>::quiet_NaN();
  double resonant_frequency_hz = std::numeric_limits<double>::quiet_NaN();
  // The sequence's [adaptive] looks within the run (when this unit may be decided in it): the run
  // so far as recorded, when the next look is due and what the one in progress saw (free-run s),
  // and the look that decided the unit (its capture then stopped).
  bool looks = false;
  PartialRun partial;
  double next_look_s = 0.0;
  double look_at_s = 0.0;
  double decided_at_s = std::numeric_limits<double>::quiet_NaN();
  std::string decided_why;
};

// Moves what the unit's capture pushed to its record; a record that cannot be written is the
// unit's fault (its capture is asked to stop).
void DrainUnit(SessionContext& ctx, UnitRun& unit, int run_id, std::vector<hw::GyroSample>& drained,
               std::vector<GyroSampleRecord>& records) {
  drained.clear();
  Drain(*unit.ring, drained);
  if (drained.empty() || !unit.outcome.ok()) return;
  records.clear();
  records.reserve(drained.size());
  for (const hw::GyroSample& sample : drained) {
    GyroSampleRecord& record = records.emplace_back(ToSampleRecord(sample, unit.release_stamp_ns));
    if (std::isfinite(record.temperature_c)) unit.temperature_c = record.temperature_c;
    record.temperature_c = unit.temperature_c;
    if (std::isfinite(record.resonant_frequency_hz))
      unit.resonant_frequency_hz = record.resonant_frequency_hz;
    record.resonant_frequency_hz = unit.resonant_frequency_hz;
  }
  unit.samples += records.size();
  if (unit.looks) {
    for (const GyroSampleRecord& record : records) {
      unit.partial.t_s.push_back(record.t_s);
      unit.partial.y.insert(unit.partial.y.end(), std::begin(record.y), std::end(record.y));
    }
  }
  if (ctx.options->on_samples && ctx.lanes.size() == 1) ctx.options->on_samples(run_id, records);
  if (auto appended = unit.lane->recorder->AppendSamples(records); !appended) {
    unit.outcome = StepOutcome::Error("record: " + appended.error().ToString());
    unit.capture->RequestStop();
  }
}

// The unit's run as the record ends it: counts, Ω, drift; the unit's fault, if any, in
// unit.outcome; `table` is the table's stop, if the run ended on one.
void EndUnitRun(SessionContext& ctx, UnitRun& unit, const SequenceRun& run, int run_id,
                const CaptureResult& result, const RunOmegaReadings& omega,
                const StepOutcome& table) {
  const SequenceConfig& seq = ctx.configs->sequence;
  UnitLane& lane = *unit.lane;
  hw::GyroElectronics& gyro = *lane.hw->gyro;
  RunEnd end;
  end.temperature_start_c = unit.start.temperature_c;
  end.frequency_start_hz = unit.start.resonant_frequency_hz;
  const hw::GyroCounters delta = result.CounterDelta();
  end.sequence_gaps = result.sequence_gaps;
  end.kernel_drops = delta.kernel_drops;
  end.bad_frames = delta.bad_frames;
  end.reference_phase_undone_samples = result.samples_reference_phase_undone;
  end.reference_phases_missing = delta.reference_phases_missing;
  if (auto status = gyro.RequestStatus(); status) {
    end.temperature_end_c = status->temperature_c;
    end.frequency_end_hz = status->resonant_frequency_hz;
  }
  const auto stopped = gyro.Stop();
  // The run's closing frames (status request, Stop and their acks) belong to this run's record,
  // not the next one's, and the last run's would otherwise never be logged.
  if (StepOutcome pumped = ctx.PumpCanLog(lane); !pumped.ok() && unit.outcome.ok())
    unit.outcome = pumped;
  StepOutcome outcome = table.ok() ? unit.outcome : table;
  if (StepOutcome measured = omega.Finish(lane.hw->axis_sign, unit.start.earth_rate_rad_s,
                                          unit.start.measured_omega_rad_s, end);
      !measured.ok() && outcome.ok()) {
    outcome = measured;
  }
  // A unit decided at a look within the run stopped its capture there: the run is complete with
  // what it holds (an interrupt's stop is the table's outcome, above, and wins).
  const bool decided = std::isfinite(unit.decided_at_s);
  if (outcome.ok() && result.termination != CaptureTermination::kCountReached &&
      !(decided && result.termination == CaptureTermination::kStopRequested)) {
    outcome =
        result.termination == CaptureTermination::kStopRequested
            ? StepOutcome::Aborted(ctx.InterruptCause() + " during run " + std::to_string(run_id))
            : StepOutcome::Error("capture of run " + std::to_string(run_id) +
                                 " ended: " + std::string(ToString(result.termination)) +
                                 " after " + std::to_string(result.samples_pushed) + " of " +
                                 std::to_string(run.Samples()) + " samples");
  }
  if (outcome.ok() && !stopped)
    outcome = StepOutcome::Error("gyro: stop: " + stopped.error().ToString());
  if (outcome.ok()) {
    if (auto drops = TooManyDrops(run_id, result.sequence_gaps,
                                  result.samples_missing + result.ring_overruns, seq.capture))
      outcome = StepOutcome::Error(std::move(*drops));
  }

  if (!outcome.ok()) {
    end.status = kRunAborted;
    end.reason = outcome.reason;
  } else {
    if (decided) {
      end.decided_at_s = unit.decided_at_s;
      end.decided_why = unit.decided_why;
      end.decided_coverage_factor = ctx.interim_limits.decision.coverage_factor;
    }
    const RunDriftJudgement drift =
        JudgeRunDrift(end.temperature_start_c, end.temperature_end_c, end.frequency_start_hz,
                      end.frequency_end_hz, seq.drift);
    if (drift.drift != RunDrift::kSteady) {
      const std::string line = "run " + std::to_string(run_id) + ": " + drift.what;
      if (drift.drift == RunDrift::kRejected) {
        end.status = kRunRejected;
        end.reason = drift.what;
        lane.result.warnings.push_back(line + " (rejected)");
      } else {
        end.reason = "flagged: " + drift.what;  // kept for the estimator, marked in the record
        lane.result.warnings.push_back(line + " (flagged)");
      }
      ctx.Log(lane, lane.result.warnings.back());
    }
  }
  if (auto ended = lane.recorder->EndRun(end); !ended && outcome.ok())
    outcome = StepOutcome::Error("record: " + ended.error().ToString());
  if (ctx.options->on_run_end && ctx.lanes.size() == 1)
    ctx.options->on_run_end(run_id, end, unit.samples);
  if (ctx.options->on_unit_run_end)
    ctx.options->on_unit_run_end(static_cast<std::size_t>(&lane - ctx.lanes.data()), run_id, end,
                                 unit.samples);
  if (outcome.ok()) {
    lane.remaining.erase(run_id);
    ctx.Log(lane, "run " + std::to_string(run_id) + " " +
                      (end.status == kRunComplete ? "complete" : end.status) + ": " +
                      std::to_string(unit.samples) +
                      " samples, Ω = " + Format("%.12g", end.omega_rad_s) + " ± " +
                      Format("%.2g", end.omega_std_error_rad_s) + " rad/s from the " +
                      end.omega_source +
                      (end.omega_source == "rate" &&
                               ctx.configs->station.table.omega_source != OmegaSourceSetting::kRate
                           ? " readings (" + omega.NoAngleReason() + ")"
                           : "") +
                      (decided ? Format("; ended when decided, %.3g s", unit.decided_at_s) +
                                     Format(" into %.3g s", run.free_run_s)
                               : ""));
  }
  if (table.ok()) unit.outcome = outcome;
}

// A look's answer for one unit of the run. Decided while its capture runs: the capture stops (the
// run is complete with what it holds). Decided after its capture had gone the run's length: the
// unit is decided after the run.
void TakeLook(SessionContext& ctx, UnitRun& unit, int run_id, LaneJudgement now) {
  const bool capturing = unit.capture && unit.capture->Running();
  const double at_s = capturing ? unit.look_at_s : kAfterTheRun;
  if (!ApplyLook(ctx, *unit.lane, run_id, std::move(now), at_s, /*whole_record=*/false)) return;
  unit.looks = false;
  if (!capturing) return;
  unit.decided_at_s = at_s;
  unit.decided_why = unit.lane->ended_early->why;
  unit.capture->RequestStop();
}

// The sequence's [adaptive] within a run: the answer of a finished look taken, then, if the look
// thread is free, the next due look started: the unit whose run so far has reached its next look
// time (every look_interval_s of free run, up to half an interval before the run's end, where the
// look after the run comes anyway; SequenceConfig::InterimLookFractions plans the same looks).
void LookWithinRun(SessionContext& ctx, std::vector<UnitRun>& units, const SequenceRun& run,
                   int run_id, const RunOmegaReadings& omega) {
  if (auto done = ctx.looks->TakeIfDone())
    TakeLook(ctx, units[done->first], run_id, std::move(done->second));
  if (ctx.looks->Busy()) return;
  const double every = ctx.configs->sequence.adaptive.look_interval_s;
  for (std::size_t i = 0; i < units.size(); ++i) {
    UnitRun& unit = units[i];
    if (!unit.looks || !unit.capture || !unit.capture->Running() || unit.partial.t_s.empty())
      continue;
    const double so_far = unit.partial.t_s.back();
    if (so_far < unit.next_look_s) continue;
    if (unit.next_look_s > run.free_run_s - 0.5 * every) {
      unit.looks = false;
      continue;
    }
    while (unit.next_look_s <= so_far) unit.next_look_s += every;
    // Ω so far, as the run's end will measure it over the whole run.
    RunEnd so_far_end;
    if (!omega
             .Finish(unit.lane->hw->axis_sign, unit.start.earth_rate_rad_s,
                     unit.start.measured_omega_rad_s, so_far_end)
             .ok() ||
        !std::isfinite(so_far_end.omega_rad_s))
      continue;
    PartialRun partial;
    partial.run_id = run_id;
    partial.omega_rad_s = so_far_end.omega_rad_s;
    partial.omega_std_rad_s = so_far_end.omega_std_error_rad_s;
    partial.t_s = unit.partial.t_s;
    partial.y = unit.partial.y;
    unit.look_at_s = so_far;
    ctx.looks->Start(
        i, [dir = unit.lane->dir, limits = &ctx.interim_limits, partial = std::move(partial)] {
          return JudgeLane(dir, /*plan_cut_short=*/true, *limits, &partial, /*threads=*/1);
        });
    return;
  }
}

}  // namespace

StepOutcome RunOne(SessionContext& ctx, const SequenceRun& run, int run_id) {
  const SequenceConfig& seq = ctx.configs->sequence;
  const BenchHardware& hw = *ctx.hw;
  Progress progress;
  progress.run = ctx.run_index;
  progress.run_count = ctx.run_count;
  progress.run_id = run_id;
  progress.omega_rad_s = run.omega_rad_s;
  progress.phase = "table";
  ctx.ReportProgress(progress, true);
  const std::int64_t run_started_ns = hw.clock->NowNs();
  if (StepOutcome settled = SettleTable(ctx, run.omega_rad_s); !settled.ok()) return settled;

  // Every unit excited first, then each waited for: their excitations overlap in time.
  progress.phase = "excite";
  ctx.ReportProgress(progress, true);
  std::vector<UnitRun> units;
  for (UnitLane& lane : ctx.lanes) {
    if (!lane.Takes(run_id)) continue;
    if (StepOutcome excited = ExciteGyro(*lane.hw->gyro, run); !excited.ok()) {
      ctx.EndUnit(lane, excited);
      continue;
    }
    units.push_back({});
    units.back().lane = &lane;
  }
  const std::int64_t ready_deadline = hw.clock->NowNs() + SecondsToNs(seq.timeouts.excite_s);
  for (UnitRun& unit : units) {
    if (unit.lane->ended) continue;
    auto ready = WaitUntilReady(ctx, *unit.lane, ready_deadline);
    if (!ready) {
      if (ready.error().table) return ready.error().outcome;
      ctx.EndUnit(*unit.lane, ready.error().outcome);
      continue;
    }
    // In the unit's own frame (an inverted unit senses −Ω and the Earth rate on −axis).
    const double sign = unit.lane->hw->axis_sign;
    unit.start.commanded_omega_rad_s = sign * run.omega_rad_s;
    unit.start.earth_rate_rad_s = sign * ctx.earth_rate_rad_s;
    unit.start.temperature_c = unit.temperature_c = ready->temperature_c;
    unit.start.resonant_frequency_hz = unit.resonant_frequency_hz = ready->resonant_frequency_hz;
    // The conditions over the run (README "The record"), when the electronics report them.
    unit.start.with_temperature = std::isfinite(unit.start.temperature_c);
    unit.start.with_resonant_frequency = std::isfinite(unit.start.resonant_frequency_hz);
  }
  std::erase_if(units, [](const UnitRun& unit) { return unit.lane->ended; });
  if (units.empty()) return StepOutcome::Ok();
  progress.samples_expected = run.Samples() * units.size();

  double measured_omega_rad_s = 0.0;
  if (auto table = hw.table->ReadStatus(); table) {
    measured_omega_rad_s = table->measured_rate_rad_s;
  } else {
    return StepOutcome::Error("rate table: " + table.error().ToString());
  }

  progress.phase = "ready";
  ctx.ReportProgress(progress, true);
  progress.phase = "release";
  ctx.ReportProgress(progress, true);
  for (UnitRun& unit : units) {
    unit.start.measured_omega_rad_s = unit.lane->hw->axis_sign * measured_omega_rad_s;
    auto release = unit.lane->hw->gyro->Release();
    if (!release) {
      unit.outcome = StepOutcome::Error("gyro: release: " + release.error().ToString());
      continue;
    }
    // The release stamp is on the transport's time base (SocketCAN: CLOCK_REALTIME), the
    // samples' too; deadlines and progress run on the bench's clock, so note the release there.
    unit.released_at_ns = hw.clock->NowNs();
    unit.release_stamp_ns = *release;
    unit.start.release_t_ns = *release;
  }
  ctx.run_overhead_s += static_cast<double>(hw.clock->NowNs() - run_started_ns) * 1e-9;
  ++ctx.runs_made;
  // One table read per loop period for the run and its margin, the release and the end.
  const auto table_reads = static_cast<std::size_t>((run.free_run_s + seq.timeouts.run_margin_s) *
                                                    1e9 / static_cast<double>(kTableReadPeriodNs));
  RunOmegaReadings omega(ctx.configs->station.table.omega_source, table_reads + 8);
  if (StepOutcome read = omega.ReadAngle(*hw.table, run_id); !read.ok()) return read;

  // Capture on one thread per unit; this thread streams to the records and keeps the table alive.
  const RealtimeConfig& rt = ctx.configs->station.realtime;
  const AdaptiveStop& adaptive = seq.adaptive;
  const bool looks_within = adaptive.stop_when_decided && adaptive.look_interval_s > 0.0;
  for (UnitRun& unit : units) {
    if (!unit.outcome.ok()) continue;
    if (auto begun = unit.lane->recorder->BeginRun(run_id, unit.start); !begun) {
      unit.outcome = StepOutcome::Error("record: " + begun.error().ToString());
      continue;
    }
    unit.begun = true;
    unit.ring = std::make_unique<SampleRing>(1u << 16);
    unit.capture = std::make_unique<CaptureThread>();
    CaptureRun capture_run;
    capture_run.sample_count = run.Samples();
    capture_run.deadline_ns =
        unit.released_at_ns + SecondsToNs(run.free_run_s + seq.timeouts.run_margin_s);
    capture_run.clock = hw.clock;
    capture_run.max_silence_ns = ctx.configs->station.gyro.sample_timeout_ms * 1'000'000;
    capture_run.external_stop = &ctx.stop_capture;
    capture_run.realtime = {rt.priority, rt.cpu, rt.lock_memory};
    if (auto started = unit.capture->Start(*unit.lane->hw->gyro, *unit.ring, capture_run); !started)
      unit.outcome = StepOutcome::Error("capture: " + started.error().message);
    unit.looks = looks_within && unit.outcome.ok() && !unit.lane->ended_early &&
                 unit.lane->CompleteRuns() + 1 >= adaptive.min_runs;
    if (unit.looks) {
      unit.partial.t_s.reserve(run.Samples());
      unit.partial.y.reserve(4 * run.Samples());
      unit.next_look_s =
          FirstLookWithinRunS(adaptive.look_interval_s, unit.lane->ShortestCompleteRunS());
    }
  }

  progress.phase = "capture";
  std::vector<hw::GyroSample> drained;
  std::vector<GyroSampleRecord> records;
  std::int64_t next_table_read = 0;
  StepOutcome outcome = StepOutcome::Ok();  // the table's
  const auto capturing = [&units] {
    for (const UnitRun& unit : units) {
      if (unit.capture && unit.capture->Running()) return true;
    }
    return false;
  };
  while (capturing()) {
    for (UnitRun& unit : units) {
      if (unit.capture) DrainUnit(ctx, unit, run_id, drained, records);
    }
    const std::int64_t now = hw.clock->NowNs();
    if (now >= next_table_read) {
      next_table_read = now + kTableReadPeriodNs;
      auto table = hw.table->ReadStatus();
      if (!table) {
        outcome = StepOutcome::Error("rate table during run " + std::to_string(run_id) + ": " +
                                     table.error().ToString());
        break;
      }
      if (table->fault) {
        outcome = StepOutcome::Error("rate table fault during run " + std::to_string(run_id) +
                                     ": " + hw::RateTableFaultName(table->fault_code));
        break;
      }
      omega.AddRate(table->measured_rate_rad_s);
      progress.table_rate_rad_s = table->measured_rate_rad_s;
      if (StepOutcome read = omega.ReadAngle(*hw.table, run_id); !read.ok()) {
        outcome = read;
        break;
      }
    }
    if (ctx.Interrupted()) {
      outcome =
          StepOutcome::Aborted(ctx.InterruptCause() + " during run " + std::to_string(run_id));
      break;
    }
    progress.samples = 0;
    progress.samples_lost = 0;
    std::int64_t released_at = now;
    for (UnitRun& unit : units) {
      if (!unit.capture) continue;
      if (StepOutcome pumped = ctx.PumpCanLog(*unit.lane); !pumped.ok() && unit.outcome.ok()) {
        unit.outcome = pumped;
        unit.capture->RequestStop();
      }
      const CaptureProgress live = unit.capture->Progress();
      progress.samples += unit.samples;
      progress.samples_lost += live.samples_missing + live.ring_overruns;
      released_at = std::min(released_at, unit.released_at_ns);
    }
    progress.elapsed_s = ctx.Seconds(now);
    progress.remaining_s = ctx.remaining_free_run_s -
                           std::min(run.free_run_s, static_cast<double>(now - released_at) * 1e-9);
    ctx.ReportProgress(progress);
    if (looks_within) LookWithinRun(ctx, units, run, run_id, omega);
    hw.clock->SleepForNs(kLoopPeriodNs);
  }
  if (!outcome.ok()) {
    for (UnitRun& unit : units) {
      if (unit.capture) unit.capture->RequestStop();
    }
  }
  // Every loop has ended (or been asked to): the joins are short.
  while (capturing()) hw.clock->SleepForNs(kLoopPeriodNs);
  std::vector<CaptureResult> results;
  for (UnitRun& unit : units) {
    results.push_back(unit.capture ? unit.capture->Join() : CaptureResult{});
    if (outcome.ok() && unit.capture) DrainUnit(ctx, unit, run_id, drained, records);
  }
  // The angle once more, now that the captures are over: the fit spans the whole run.
  if (outcome.ok()) {
    if (StepOutcome read = omega.ReadAngle(*hw.table, run_id); !read.ok()) outcome = read;
  }
  // A look still running is waited for (the table kept meanwhile): its unit may be decided.
  if (outcome.ok() && looks_within && ctx.looks->Busy()) {
    auto done = AwaitLook(ctx, kLoopPeriodNs);
    if (!done) {
      outcome = done.error();
    } else {
      TakeLook(ctx, units[done->first], run_id, std::move(done->second));
    }
  }

  progress.phase = "stop";
  ctx.ReportProgress(progress, true);
  for (std::size_t i = 0; i < units.size(); ++i) {
    UnitRun& unit = units[i];
    if (unit.begun) {
      EndUnitRun(ctx, unit, run, run_id, results[i], omega, outcome);
    } else {
      StopGyro(*unit.lane->hw);
    }
    if (outcome.ok() && !unit.outcome.ok()) ctx.EndUnit(*unit.lane, unit.outcome);
  }
  ctx.remaining_free_run_s = std::max(0.0, ctx.remaining_free_run_s - run.free_run_s);
  return outcome;
}

}  // namespace hrgbench::bench::internal
