#pragma once
// Drives one free run through the hw interfaces by hand, as the bench's sequencer does:
// table to Ω → WaitUntilStable → Configure → Excite → WaitReady → Release → ReadSamples for the
// run's length (heartbeating the table) → gyro Stop. Failures are returned as text naming the step.

#include <cstdint>
#include <expected>
#include <string>
#include <vector>

#include "hrgbench/hw/gyro_electronics.hpp"
#include "hrgbench/hw/rate_table.hpp"

namespace hrgbench::testing {

struct FreeRun {
  double omega_rad_s = 0.0;  // commanded table rate
  hw::RateTableStatus stable_status;
  std::int64_t t0_ns = 0;
  std::vector<hw::GyroSample> samples;
  hw::GyroReadStatus last_read = hw::GyroReadStatus::kOk;
};

inline hw::StableCriteria TestCriteria() {
  hw::StableCriteria c;
  c.tolerance_rad_s = 1e-3;
  c.dwell_s = 0.5;
  c.timeout_s = 10.0;
  c.poll_period_s = 0.05;
  return c;
}

// Reads until `n` samples or a non-ok status (kept in run->last_read).
inline void ReadSamples(hw::GyroElectronics& gyro, std::size_t n, FreeRun* run,
                        std::int64_t timeout_ns = 100'000'000) {
  run->samples.reserve(n);
  hw::GyroSample chunk[64];
  while (run->samples.size() < n) {
    const std::size_t want = std::min<std::size_t>(64, n - run->samples.size());
    const hw::GyroReadResult r = gyro.ReadSamples(std::span(chunk, want), timeout_ns);
    run->samples.insert(run->samples.end(), chunk, chunk + r.count);
    run->last_read = r.status;
    if (r.status != hw::GyroReadStatus::kOk) return;
  }
}

inline std::expected<FreeRun, std::string> DoFreeRun(hw::RateTable& table,
                                                     hw::GyroElectronics& gyro, double omega_rad_s,
                                                     const hw::WaveState& wave, std::size_t samples,
                                                     std::uint32_t rate_hz = 1000) {
  FreeRun run;
  run.omega_rad_s = omega_rad_s;
  if (auto ok = table.SetRate(omega_rad_s); !ok)
    return std::unexpected("SetRate: " + ok.error().ToString());
  auto stable = table.WaitUntilStable(TestCriteria());
  if (!stable) return std::unexpected("WaitUntilStable: " + stable.error().ToString());
  run.stable_status = *stable;
  if (auto ok = gyro.Configure({rate_hz}); !ok)
    return std::unexpected("Configure: " + ok.error().ToString());
  if (auto ok = gyro.Excite(wave); !ok) return std::unexpected("Excite: " + ok.error().ToString());
  if (auto ok = gyro.WaitReady(2'000'000'000); !ok)
    return std::unexpected("WaitReady: " + ok.error().ToString());
  auto t0 = gyro.Release();
  if (!t0) return std::unexpected("Release: " + t0.error().ToString());
  run.t0_ns = *t0;
  // Read in 100 ms chunks and keep the table's watchdog fed between them, as the sequencer does.
  for (std::size_t n = std::min<std::size_t>(samples, rate_hz / 10); run.samples.size() < samples;
       n = std::min(samples, n + rate_hz / 10)) {
    ReadSamples(gyro, n, &run);
    if (run.last_read != hw::GyroReadStatus::kOk) break;
    if (auto ok = table.Heartbeat(); !ok)
      return std::unexpected("Heartbeat: " + ok.error().ToString());
  }
  if (auto ok = gyro.Stop(); !ok) return std::unexpected("Stop: " + ok.error().ToString());
  return run;
}

}  // namespace hrgbench::testing
