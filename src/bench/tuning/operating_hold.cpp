// One constant-rate hold of the gyro as a gyro: the table, the operating mode, the rate error.

#include "hrgbench/bench/tuning/operating_hold.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>

#include "bench/sequencer/run_omega_readings.hpp"
#include "bench/sequencer/table_settle.hpp"
#include "hrgbench/hw/operating_gyro.hpp"

namespace hrgbench::bench {
namespace {

constexpr std::size_t kChunk = 256;
constexpr std::int64_t kReadTimeoutNs = 200'000'000;  // a silent stream for this long is lost

OperatingHold Failed(OperatingHold hold, std::string why) {
  hold.ok = false;
  hold.why = std::move(why);
  return hold;
}

bool Stopped(const std::atomic<int>* stop) {
  return stop != nullptr && stop->load(std::memory_order_acquire) != 0;
}

using hw::SecondsToNs;

}  // namespace

OperatingHold RunOperatingHold(const BenchHardware& hardware, const UnitHardware& unit,
                               const OperatingHoldPlan& plan, double earth_rate_rad_s,
                               const std::atomic<int>* stop) {
  OperatingHold hold;
  hold.omega_set_rad_s = plan.omega_rad_s;
  if (hardware.table == nullptr || hardware.clock == nullptr || unit.gyro == nullptr ||
      unit.operating == nullptr) {
    return Failed(hold, "the station gives no operating-mode access to this unit's electronics");
  }
  // The duration, bounded before anything moves.
  double duration_s = plan.duration_s;
  if (!(duration_s > 0.0)) {
    const double turn_rate = 4.0 * std::abs(plan.angular_gain * plan.omega_rad_s);
    if (!(turn_rate > 0.0) || !(plan.turns > 0.0))
      return Failed(hold, "a hold at zero rate needs a duration (duration_s > 0)");
    duration_s = plan.turns * 2.0 * std::numbers::pi / turn_rate;
  }
  const double samples_wanted = std::ceil(duration_s * plan.sample_rate_hz);
  if (!std::isfinite(duration_s) || duration_s > OperatingHoldPlan::kMaxDurationS ||
      plan.sample_rate_hz == 0 ||
      samples_wanted > static_cast<double>(OperatingHoldPlan::kMaxSamples)) {
    return Failed(hold, "a hold of " + std::to_string(duration_s) + " s at " +
                            std::to_string(plan.sample_rate_hz) +
                            " samples/s is beyond the bounds (" +
                            std::to_string(OperatingHoldPlan::kMaxDurationS) + " s, " +
                            std::to_string(OperatingHoldPlan::kMaxSamples) + " samples)");
  }
  const auto n = static_cast<std::size_t>(samples_wanted);
  hold.duration_s = static_cast<double>(n) / plan.sample_rate_hz;

  hw::RateTable& table = *hardware.table;
  hw::Clock& clock = *hardware.clock;
  hw::GyroElectronics& gyro = *unit.gyro;
  hw::OperatingGyro& operating = *unit.operating;
  const double table_rate_rad_s = unit.axis_sign * plan.omega_rad_s;
  if (auto set = table.SetRate(table_rate_rad_s); !set)
    return Failed(
        hold, "table to " + std::to_string(table_rate_rad_s) + " rad/s: " + set.error().ToString());
  const internal::TableSettleResult settled = internal::WaitTableSettled(
      table, clock, plan.stable, plan.settle_timeout_s, [stop] { return Stopped(stop); });
  switch (settled.end) {
    case internal::TableSettle::kStable:
      break;
    case internal::TableSettle::kStopped:
      return Failed(hold, "stopped while the table settled");
    case internal::TableSettle::kTimedOut:
      return Failed(hold, "table not stable at " + std::to_string(table_rate_rad_s) +
                              " rad/s within " + std::to_string(plan.settle_timeout_s) + " s");
    case internal::TableSettle::kTableError:
      return Failed(hold, "table at rate: " + settled.table_error);
  }

  const auto gyro_failed = [&](const char* step, const hw::GyroError& error) {
    (void)gyro.Stop();
    return Failed(hold, std::string("gyro ") + step + ": " + error.ToString());
  };
  if (auto configured = gyro.Configure({plan.sample_rate_hz, true}); !configured)
    return gyro_failed("configure (operating mode)", configured.error());
  if (auto excited = gyro.Excite(plan.wave); !excited)
    return gyro_failed("excite", excited.error());
  if (auto ready = gyro.WaitReady(SecondsToNs(plan.ready_timeout_s)); !ready)
    return gyro_failed("ready", ready.error());
  const std::uint64_t gaps_before = gyro.Counters().sequence_gaps;
  if (auto released = gyro.Release(); !released) return gyro_failed("release", released.error());
  if (gyro.State() != hw::GyroMode::kOperating) {
    (void)gyro.Stop();
    return Failed(hold, std::string("gyro: released into mode ") +
                            std::string(hw::ToString(gyro.State())) + ", not operating");
  }

  // The table's Ω over the hold, as a run's (angle when the table reports it, else its rates).
  const auto polls = static_cast<std::size_t>(hold.duration_s / plan.poll_period_s) + 8;
  internal::RunOmegaReadings omega(OmegaSourceSetting::kAngleWhenReported, polls);
  std::vector<hw::OperatingSample> samples(n);
  std::size_t got = 0;
  std::int64_t next_poll_ns = clock.NowNs();
  std::string table_problem;
  while (got < n) {
    if (Stopped(stop)) {
      (void)gyro.Stop();
      return Failed(hold, "stopped");
    }
    if (clock.NowNs() >= next_poll_ns) {
      next_poll_ns += SecondsToNs(plan.poll_period_s);
      auto status = table.ReadStatus();  // also keeps the table's watchdog fed
      if (!status) {
        table_problem = "table status: " + status.error().ToString();
        break;
      }
      if (status->fault) {
        table_problem = "table fault " + std::to_string(status->fault_code);
        break;
      }
      omega.AddRate(status->measured_rate_rad_s);
      if (auto read = omega.ReadAngle(table, 0); !read.ok()) {
        table_problem = read.reason;
        break;
      }
    }
    const std::size_t want = std::min(kChunk, n - got);
    const std::size_t read =
        operating.ReadOperatingSamples(std::span(samples).subspan(got, want), kReadTimeoutNs);
    if (read == 0 && gyro.State() != hw::GyroMode::kOperating) {
      table_problem = std::string("gyro left the operating mode (") +
                      std::string(hw::ToString(gyro.State())) + ")";
      break;
    }
    if (read == 0) {
      table_problem =
          "gyro: no operating sample for " + std::to_string(kReadTimeoutNs / 1'000'000) + " ms";
      break;
    }
    got += read;
  }
  // One last angle after the capture: the table's mean spans the whole hold.
  if (table_problem.empty()) {
    if (auto read = omega.ReadAngle(table, 0); !read.ok()) table_problem = read.reason;
  }
  hold.sequence_gaps = gyro.Counters().sequence_gaps - gaps_before;
  hold.loops = operating.OperatingLoopsSinceRelease();  // before Stop: reset at the next release
  if (auto stopped = gyro.Stop(); !stopped && table_problem.empty())
    table_problem = "gyro stop: " + stopped.error().ToString();
  hold.samples = got;
  if (!table_problem.empty()) return Failed(hold, table_problem);

  RunEnd end;
  if (auto measured = omega.Finish(unit.axis_sign, unit.axis_sign * earth_rate_rad_s,
                                   table_rate_rad_s * unit.axis_sign, end);
      !measured.ok()) {
    return Failed(hold, measured.reason);
  }
  hold.omega_rad_s = end.omega_rad_s;
  hold.omega_std_error_rad_s = end.omega_std_error_rad_s;
  hold.omega_source = end.omega_source;

  // Rates from the angle output's increments; the wave angle unwrapped from its π period.
  const double rate_hz = plan.sample_rate_hz;
  hold.rate_error_rad_s.reserve(got);
  hold.wave_angle_rad.reserve(got);
  double theta = samples[0].wave_angle_rad;
  for (std::size_t k = 1; k < got; ++k) {
    const std::uint64_t step = samples[k].index - samples[k - 1].index;
    theta +=
        std::remainder(samples[k].wave_angle_rad - samples[k - 1].wave_angle_rad, std::numbers::pi);
    hold.wave_angle_rad.push_back(theta);
    hold.rate_error_rad_s.push_back(
        (samples[k].angle_output_rad - samples[k - 1].angle_output_rad) * rate_hz /
            static_cast<double>(std::max<std::uint64_t>(step, 1)) -
        hold.omega_rad_s);
  }
  hold.ok = true;
  if (plan.harmonics == 0) return hold;  // a zero-rate hold: the wave does not turn
  hold.fit = analysis::FitRateErrorHarmonics(hold.wave_angle_rad, hold.rate_error_rad_s,
                                             1.0 / rate_hz, plan.window_samples, plan.harmonics);
  if (!hold.fit.ok) return Failed(hold, "rate error harmonics: " + hold.fit.why);
  return hold;
}

}  // namespace hrgbench::bench
