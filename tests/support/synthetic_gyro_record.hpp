#pragma once
// Synthetic gyro samples and a session header for recorder tests (STYLE rule 12: provenance).
// Generator: y1..y4 = a decaying standing wave, y_c(t) = A e^{-t/τ} cos(2π f t + c π/4) plus
// uniform noise from std::mt19937_64(seed + run_id) in [-1e-4, 1e-4]; A = 1, τ = 50 s, f = 3 Hz.
// t_s = k / fs exactly (k = 0 … n−1). Optional columns: measured Ω = plan Ω + 1e-6·sin(t),
// temperature 25 + 0.01·t °C. Values need not be physical; they must only be exact after a
// round trip through the files.

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "hrgbench/session/session_record_types.hpp"

namespace hrgbench::testing {

inline constexpr std::uint64_t kSyntheticSeed = 20240501;

inline std::vector<bench::GyroSampleRecord> SyntheticSamples(int run_id, std::size_t n,
                                                             double sample_rate_hz,
                                                             double omega_rad_s = 0.0) {
  std::mt19937_64 rng(kSyntheticSeed + static_cast<std::uint64_t>(run_id));
  std::uniform_real_distribution<double> noise(-1e-4, 1e-4);
  std::vector<bench::GyroSampleRecord> out(n);
  constexpr double kPi = 3.14159265358979323846;
  for (std::size_t k = 0; k < n; ++k) {
    bench::GyroSampleRecord& s = out[k];
    s.seq = static_cast<std::uint32_t>(k);
    s.t_s = static_cast<double>(k) / sample_rate_hz;
    for (int c = 0; c < 4; ++c) {
      s.y[c] = std::exp(-s.t_s / 50.0) * std::cos(2 * kPi * 3.0 * s.t_s + c * kPi / 4) + noise(rng);
    }
    s.measured_omega_rad_s = omega_rad_s + 1e-6 * std::sin(s.t_s);
    s.temperature_c = 25.0 + 0.01 * s.t_s;
    s.resonant_frequency_hz = 5012.5 - 0.001 * std::floor(10.0 * s.t_s);  // 10 Hz status, 1 mHz
  }
  return out;
}

// A plan of `runs` runs at Ω = 0.1·id rad/s, 1 kHz, 0.5 s each.
inline bench::SessionHeader SyntheticHeader(int runs = 3, double sample_rate_hz = 1000.0) {
  bench::SessionHeader header;
  header.unit_serial = "HRG-TEST-0001";
  header.station_name = "test-station";
  header.software_version = "test-build";
  header.config_sha256 = {std::string(64, 'a'), std::string(64, 'b'), std::string(64, 'c')};
  header.realtime_status = "not permitted: running without SCHED_FIFO (test)";
  header.can_interface = "vcan0";
  for (int id = 1; id <= runs; ++id) {
    header.runs.push_back(bench::PlannedRun{id, 0.1 * id, 1.0, 0.0, 0.1 * id, 0.5, sample_rate_hz});
  }
  return header;
}

}  // namespace hrgbench::testing
