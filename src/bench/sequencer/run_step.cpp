// One free run: table to Ω, settle, excite, ready, release, capture, stop, judge, record.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "bench/sequencer/run_context.hpp"
#include "bench/sequencer/run_omega_readings.hpp"

namespace hrgbench::bench::internal {
namespace {

constexpr std::int64_t kNsPerS = 1'000'000'000;
// Driver waits are cut into slices this long so an interrupt is seen within one slice; on a table
// the dwell restarts with each slice, so a slice is the dwell plus this.
constexpr double kWaitSliceS = 0.5;
// How often the run loop drains the ring, reads the table and reports progress (hardware clock).
constexpr std::int64_t kLoopPeriodNs = 20'000'000;
constexpr std::int64_t kTableReadPeriodNs = 20'000'000;

std::int64_t Ns(double seconds) { return static_cast<std::int64_t>(std::llround(seconds * 1e9)); }

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
  const std::int64_t deadline = ctx.hw->clock->NowNs() + Ns(seq.timeouts.settle_s);
  hw::StableCriteria criteria;
  criteria.tolerance_rad_s = seq.settle.rate_tolerance_rad_s;
  criteria.dwell_s = seq.settle.dwell_s;
  criteria.poll_period_s = seq.settle.poll_period_s;
  for (;;) {
    if (ctx.Interrupted())
      return StepOutcome::Aborted(ctx.InterruptCause() + " while the table settled");
    const double left_s = static_cast<double>(deadline - ctx.hw->clock->NowNs()) * 1e-9;
    if (left_s <= 0.0)
      return StepOutcome::Error("rate table not stable at " + Format("%g", omega_rad_s) +
                                " rad/s within " + Format("%g", seq.timeouts.settle_s) + " s");
    criteria.timeout_s = std::min(left_s, criteria.dwell_s + kWaitSliceS);
    criteria.timeout_s = std::max(criteria.timeout_s, criteria.dwell_s);
    auto stable = ctx.hw->table->WaitUntilStable(criteria);
    if (stable) return StepOutcome::Ok();
    if (stable.error().code != hw::RateTableErrorCode::kNotStable)
      return StepOutcome::Error("rate table: " + stable.error().ToString());
    if (StepOutcome pumped = ctx.PumpCanLog(); !pumped.ok()) return pumped;
  }
}

// Gyro configured, excited and ready; returns the ready status.
std::expected<hw::GyroStatus, StepOutcome> ExciteGyro(SessionContext& ctx, const SequenceRun& run) {
  hw::GyroElectronics& gyro = *ctx.hw->gyro;
  if (gyro.State() != hw::GyroMode::kConfigured && gyro.State() != hw::GyroMode::kReady) {
    if (auto configured = gyro.Configure({.sample_rate_hz = run.sample_rate_hz}); !configured)
      return std::unexpected(StepOutcome::Error("gyro: configure: " + configured.error().ToString()));
  }
  if (auto excited = gyro.Excite({run.a, run.b, run.theta_rad}); !excited)
    return std::unexpected(StepOutcome::Error("gyro: excite: " + excited.error().ToString()));
  const std::int64_t deadline = ctx.hw->clock->NowNs() + Ns(ctx.configs->sequence.timeouts.excite_s);
  for (;;) {
    if (ctx.Interrupted())
      return std::unexpected(StepOutcome::Aborted(ctx.InterruptCause() + " during excitation"));
    const std::int64_t left = deadline - ctx.hw->clock->NowNs();
    if (left <= 0)
      return std::unexpected(StepOutcome::Error(
          "gyro not ready within " + Format("%g", ctx.configs->sequence.timeouts.excite_s) + " s"));
    auto ready = gyro.WaitReady(std::min(left, Ns(kWaitSliceS)));
    if (StepOutcome pumped = ctx.PumpCanLog(); !pumped.ok()) return std::unexpected(pumped);
    if (ready) return *ready;
    if (ready.error().code != hw::GyroErrorCode::kTimeout)
      return std::unexpected(StepOutcome::Error("gyro: " + ready.error().ToString()));
  }
}

double RelativeChange(double start, double end) {
  if (!std::isfinite(start) || !std::isfinite(end) || start == 0.0) return 0.0;
  return std::abs(end - start) / std::abs(start);
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
  progress.samples_expected = run.Samples();
  progress.phase = "table";
  ctx.ReportProgress(progress, true);
  if (StepOutcome settled = SettleTable(ctx, run.omega_rad_s); !settled.ok()) return settled;

  progress.phase = "excite";
  ctx.ReportProgress(progress, true);
  auto ready = ExciteGyro(ctx, run);
  if (!ready) return ready.error();

  RunStart start;
  start.commanded_omega_rad_s = run.omega_rad_s;
  start.earth_rate_rad_s = ctx.earth_rate_rad_s;
  start.temperature_c = ready->temperature_c;
  start.resonant_frequency_hz = ready->resonant_frequency_hz;
  if (auto table = hw.table->ReadStatus(); table) {
    start.measured_omega_rad_s = table->measured_rate_rad_s;
  } else {
    return StepOutcome::Error("rate table: " + table.error().ToString());
  }

  progress.phase = "ready";
  ctx.ReportProgress(progress, true);
  progress.phase = "release";
  ctx.ReportProgress(progress, true);
  auto release = hw.gyro->Release();
  if (!release) return StepOutcome::Error("gyro: release: " + release.error().ToString());
  // The release stamp is on the transport's time base (SocketCAN: CLOCK_REALTIME), the samples'
  // too; deadlines and progress run on the bench's clock, so note the release there as well.
  const std::int64_t released_at = hw.clock->NowNs();
  // One table read per loop period for the run and its margin, the release and the end.
  const auto table_reads = static_cast<std::size_t>((run.free_run_s + seq.timeouts.run_margin_s) *
                                                    1e9 / static_cast<double>(kTableReadPeriodNs));
  RunOmegaReadings omega(ctx.configs->station.table.omega_source, table_reads + 8);
  if (StepOutcome read = omega.ReadAngle(*hw.table, run_id); !read.ok()) {
    MakeSafe(hw);
    return read;
  }
  start.release_t_ns = *release;
  if (auto begun = ctx.recorder->BeginRun(run_id, start); !begun)
    return StepOutcome::Error("record: " + begun.error().ToString());

  // Capture on its own thread; this thread streams to the record and keeps the table alive.
  SampleRing ring(1u << 16);
  CaptureThread capture;
  CaptureRun capture_run;
  capture_run.sample_count = run.Samples();
  capture_run.deadline_ns = released_at + Ns(run.free_run_s + seq.timeouts.run_margin_s);
  capture_run.clock = hw.clock;
  capture_run.max_silence_ns = ctx.configs->station.gyro.sample_timeout_ms * 1'000'000;
  capture_run.external_stop = &ctx.stop_capture;
  const RealtimeConfig& rt = ctx.configs->station.realtime;
  capture_run.realtime = {rt.priority, rt.cpu, rt.lock_memory};
  if (auto started = capture.Start(*hw.gyro, ring, capture_run); !started) {
    MakeSafe(hw);
    return StepOutcome::Error("capture: " + started.error().message);
  }

  progress.phase = "capture";
  std::vector<hw::GyroSample> drained;
  std::vector<GyroSampleRecord> records;
  std::int64_t next_table_read = 0;
  StepOutcome outcome = StepOutcome::Ok();
  const auto drain = [&]() -> bool {
    drained.clear();
    Drain(ring, drained);
    records.resize(drained.size());
    for (std::size_t i = 0; i < drained.size(); ++i)
      records[i] = ToSampleRecord(drained[i], *release);
    if (records.empty()) return true;
    progress.samples += records.size();
    if (ctx.options->on_samples) ctx.options->on_samples(run_id, records);
    if (auto appended = ctx.recorder->AppendSamples(records); !appended) {
      outcome = StepOutcome::Error("record: " + appended.error().ToString());
      return false;
    }
    return true;
  };
  while (capture.Running()) {
    if (!drain()) break;
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
    if (StepOutcome pumped = ctx.PumpCanLog(); !pumped.ok()) {
      outcome = pumped;
      break;
    }
    const CaptureProgress live = capture.Progress();
    progress.samples_lost = live.samples_missing + live.ring_overruns;
    progress.elapsed_s = ctx.Seconds(now);
    progress.remaining_s = ctx.remaining_free_run_s -
                           std::min(run.free_run_s, static_cast<double>(now - released_at) * 1e-9);
    ctx.ReportProgress(progress);
    hw.clock->SleepForNs(kLoopPeriodNs);
  }
  if (!outcome.ok()) capture.RequestStop();
  // Running() is false (or the stop was requested): the join is short.
  while (capture.Running()) hw.clock->SleepForNs(kLoopPeriodNs);
  const CaptureResult result = capture.Join();
  if (outcome.ok()) drain();
  // The angle once more, now that the capture is over: the fit spans the whole run.
  if (outcome.ok()) {
    if (StepOutcome read = omega.ReadAngle(*hw.table, run_id); !read.ok()) outcome = read;
  }
  if (StepOutcome pumped = ctx.PumpCanLog(); !pumped.ok() && outcome.ok()) outcome = pumped;

  progress.phase = "stop";
  ctx.ReportProgress(progress, true);
  RunEnd end;
  end.temperature_start_c = start.temperature_c;
  end.frequency_start_hz = start.resonant_frequency_hz;
  const hw::GyroCounters delta = result.CounterDelta();
  end.sequence_gaps = result.sequence_gaps;
  end.kernel_drops = delta.kernel_drops;
  end.bad_frames = delta.bad_frames;
  end.reference_phase_undone_samples = result.samples_reference_phase_undone;
  end.reference_phases_missing = delta.reference_phases_missing;
  if (auto status = hw.gyro->RequestStatus(); status) {
    end.temperature_end_c = status->temperature_c;
    end.frequency_end_hz = status->resonant_frequency_hz;
  }
  const auto stopped = hw.gyro->Stop();
  // The run's closing frames (status request, Stop and their acks) belong to this run's record,
  // not the next one's, and the last run's would otherwise never be logged.
  if (StepOutcome pumped = ctx.PumpCanLog(); !pumped.ok() && outcome.ok()) outcome = pumped;
  if (StepOutcome measured = omega.Finish(ctx.earth_rate_rad_s, start.measured_omega_rad_s, end);
      !measured.ok() && outcome.ok()) {
    outcome = measured;
  }

  if (outcome.ok() && result.termination != CaptureTermination::kCountReached) {
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
  const std::uint64_t lost = result.samples_missing + result.ring_overruns;
  if (outcome.ok() && (static_cast<std::int64_t>(result.sequence_gaps) > seq.capture.max_sequence_gaps ||
                       static_cast<std::int64_t>(lost) > seq.capture.max_samples_lost)) {
    outcome = StepOutcome::Error("too many drops in run " + std::to_string(run_id) + ": " +
                                 std::to_string(result.sequence_gaps) + " gaps, " +
                                 std::to_string(lost) + " samples lost (allowed " +
                                 std::to_string(seq.capture.max_sequence_gaps) + ", " +
                                 std::to_string(seq.capture.max_samples_lost) + ")");
  }

  if (!outcome.ok()) {
    end.status = kRunAborted;
    end.reason = outcome.reason;
  } else {
    // The paper estimates only when temperature is stationary (change < 1 %).
    const double temperature_change = RelativeChange(end.temperature_start_c, end.temperature_end_c);
    const double frequency_change = RelativeChange(end.frequency_start_hz, end.frequency_end_hz);
    std::string drift;
    if (temperature_change > seq.drift.max_temperature_change_rel)
      drift = "temperature changed by " + Format("%.3g %%", 100 * temperature_change);
    if (seq.drift.max_frequency_change_rel && frequency_change > *seq.drift.max_frequency_change_rel)
      drift += (drift.empty() ? "" : ", ") +
               ("resonant frequency changed by " + Format("%.3g %%", 100 * frequency_change));
    if (!drift.empty()) {
      const std::string line = "run " + std::to_string(run_id) + ": " + drift;
      if (seq.drift.action == DriftAction::kReject) {
        end.status = kRunRejected;
        end.reason = drift;
        ctx.warnings.push_back(line + " (rejected)");
      } else {
        end.reason = "flagged: " + drift;  // kept for the estimator, marked in the record
        ctx.warnings.push_back(line + " (flagged)");
      }
      ctx.Log(ctx.warnings.back());
    }
  }
  if (auto ended = ctx.recorder->EndRun(end); !ended && outcome.ok())
    outcome = StepOutcome::Error("record: " + ended.error().ToString());
  ctx.remaining_free_run_s = std::max(0.0, ctx.remaining_free_run_s - run.free_run_s);
  if (ctx.options->on_run_end) ctx.options->on_run_end(run_id, end, progress.samples);
  if (outcome.ok()) {
    ctx.Log("run " + std::to_string(run_id) + " " +
            (end.status == kRunComplete ? "complete" : end.status) + ": " +
            std::to_string(progress.samples) + " samples, Ω = " + Format("%.12g", end.omega_rad_s) +
            " ± " + Format("%.2g", end.omega_std_error_rad_s) + " rad/s from the " +
            end.omega_source +
            (end.omega_source == "rate" &&
                     ctx.configs->station.table.omega_source != OmegaSourceSetting::kRate
                 ? " readings (" + omega.NoAngleReason() + ")"
                 : ""));
  }
  return outcome;
}

}  // namespace hrgbench::bench::internal
