// Warm-up before the first run: at least min_s, then until the gyro's temperature moves by no more
// than max_drift_c over the last window_s, or ERROR after timeout_s. Temperature from the
// electronics' status (RequestStatus); the samples are kept in a short history.
#include <algorithm>
#include <cstdio>
#include <deque>
#include <utility>

#include "bench/sequencer/run_context.hpp"

namespace hrgbench::bench::internal {

StepOutcome WaitForWarmup(SessionContext& ctx) {
  const WarmupCriteria& warmup = ctx.configs->sequence.warmup;
  hw::Clock& clock = *ctx.hw->clock;
  hw::GyroElectronics& gyro = *ctx.hw->gyro;
  const std::int64_t start = clock.NowNs();
  const auto s_since = [&](std::int64_t t) { return static_cast<double>(t - start) * 1e-9; };
  // A tenth of the window between readings, at most 1 s: enough points to see a drift.
  const double period_s = std::clamp(warmup.window_s / 10.0, 0.05, 1.0);
  std::deque<std::pair<double, double>> history;  // (t_s, temperature_c)
  Progress progress;
  progress.phase = "warm-up";
  progress.run_count = ctx.run_count;
  if (gyro.State() == hw::GyroMode::kIdle || gyro.State() == hw::GyroMode::kStopped) {
    const std::uint32_t rate = ctx.configs->sequence.runs.front().sample_rate_hz;
    if (auto configured = gyro.Configure({.sample_rate_hz = rate}); !configured)
      return StepOutcome::Error("gyro: configure: " + configured.error().ToString());
  }
  for (;;) {
    if (ctx.Interrupted()) return StepOutcome::Aborted(ctx.InterruptCause() + " during warm-up");
    const std::int64_t now = clock.NowNs();
    const double t = s_since(now);
    auto status = gyro.RequestStatus();
    if (!status) return StepOutcome::Error("gyro: status during warm-up: " + status.error().ToString());
    history.emplace_back(t, status->temperature_c);
    while (!history.empty() && history.front().first < t - warmup.window_s - 1e-9)
      history.pop_front();
    if (t >= warmup.min_s && !history.empty() &&
        history.back().first - history.front().first >= warmup.window_s - period_s - 1e-9) {
      const auto [lo, hi] = std::minmax_element(
          history.begin(), history.end(),
          [](const auto& a, const auto& b) { return a.second < b.second; });
      if (hi->second - lo->second <= warmup.max_drift_c) {
        char line[128];
        std::snprintf(line, sizeof line, "warm: %.2f °C, drift %.3f °C over %.0f s (after %.0f s)",
                      status->temperature_c, hi->second - lo->second, warmup.window_s, t);
        ctx.Log(line);
        return StepOutcome::Ok();
      }
    }
    if (t > warmup.timeout_s) {
      char line[160];
      std::snprintf(line, sizeof line,
                    "gyro not warm after %.0f s: temperature still drifts more than %.3g °C "
                    "over %.0f s",
                    warmup.timeout_s, warmup.max_drift_c, warmup.window_s);
      return StepOutcome::Error(line);
    }
    progress.elapsed_s = ctx.Seconds(now);
    ctx.ReportProgress(progress);
    if (StepOutcome pumped = ctx.PumpCanLog(); !pumped.ok()) return pumped;
    clock.SleepForNs(static_cast<std::int64_t>(period_s * 1e9));
  }
}

}  // namespace hrgbench::bench::internal
