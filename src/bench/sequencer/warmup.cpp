// Warm-up before the first run: at least min_s, then until each gyro's temperature moves by no
// more than max_drift_c over the last window_s. A unit still drifting after timeout_s is not warm:
// its session ends as ERROR and the others go on. Temperature from the electronics' status
// (RequestStatus); the readings are kept in a short history per unit.
#include <algorithm>
#include <cstdio>
#include <deque>
#include <utility>

#include "bench/sequencer/run_context.hpp"

namespace hrgbench::bench::internal {
namespace {

// One unit's readings: (t_s, temperature_c) over the last window.
struct WarmupHistory {
  UnitLane* lane = nullptr;
  std::deque<std::pair<double, double>> readings;
  bool warm = false;
};

}  // namespace

StepOutcome WaitForWarmup(SessionContext& ctx) {
  const WarmupCriteria& warmup = ctx.configs->sequence.warmup;
  hw::Clock& clock = *ctx.hw->clock;
  const std::int64_t start = clock.NowNs();
  const auto s_since = [&](std::int64_t t) { return static_cast<double>(t - start) * 1e-9; };
  // A tenth of the window between readings, at most 1 s: enough points to see a drift.
  const double period_s = std::clamp(warmup.window_s / 10.0, 0.05, 1.0);
  Progress progress;
  progress.phase = "warm-up";
  progress.run_count = ctx.run_count;
  std::vector<WarmupHistory> units;
  for (UnitLane& lane : ctx.lanes) {
    if (lane.ended || lane.remaining.empty()) continue;
    hw::GyroElectronics& gyro = *lane.hw->gyro;
    if (gyro.State() == hw::GyroMode::kIdle || gyro.State() == hw::GyroMode::kStopped) {
      const std::uint32_t rate = ctx.configs->sequence.runs.front().sample_rate_hz;
      if (auto configured = gyro.Configure({.sample_rate_hz = rate}); !configured) {
        ctx.EndUnit(lane, StepOutcome::Error("gyro: configure: " + configured.error().ToString()));
        continue;
      }
    }
    units.push_back({&lane, {}, false});
  }
  for (;;) {
    if (ctx.Interrupted()) return StepOutcome::Aborted(ctx.InterruptCause() + " during warm-up");
    const std::int64_t now = clock.NowNs();
    const double t = s_since(now);
    bool all_warm = true;
    for (WarmupHistory& unit : units) {
      if (unit.warm || unit.lane->ended) continue;
      auto status = unit.lane->hw->gyro->RequestStatus();
      if (!status) {
        ctx.EndUnit(*unit.lane, StepOutcome::Error("gyro: status during warm-up: " +
                                                   status.error().ToString()));
        continue;
      }
      auto& history = unit.readings;
      history.emplace_back(t, status->temperature_c);
      while (!history.empty() && history.front().first < t - warmup.window_s - 1e-9)
        history.pop_front();
      if (t >= warmup.min_s && !history.empty() &&
          history.back().first - history.front().first >= warmup.window_s - period_s - 1e-9) {
        const auto [lo, hi] =
            std::minmax_element(history.begin(), history.end(),
                                [](const auto& a, const auto& b) { return a.second < b.second; });
        if (hi->second - lo->second <= warmup.max_drift_c) {
          char line[128];
          std::snprintf(line, sizeof line,
                        "warm: %.2f °C, drift %.3f °C over %.0f s (after %.0f s)",
                        status->temperature_c, hi->second - lo->second, warmup.window_s, t);
          ctx.Log(*unit.lane, line);
          unit.warm = true;
          continue;
        }
      }
      if (t > warmup.timeout_s) {
        char line[160];
        std::snprintf(line, sizeof line,
                      "gyro not warm after %.0f s: temperature still drifts more than %.3g °C "
                      "over %.0f s",
                      warmup.timeout_s, warmup.max_drift_c, warmup.window_s);
        ctx.EndUnit(*unit.lane, StepOutcome::Error(line));
        continue;
      }
      all_warm = false;
    }
    if (all_warm) return StepOutcome::Ok();
    progress.elapsed_s = ctx.Seconds(now);
    ctx.ReportProgress(progress);
    ctx.PumpCanLogs();
    clock.SleepForNs(static_cast<std::int64_t>(period_s * 1e9));
  }
}

}  // namespace hrgbench::bench::internal
