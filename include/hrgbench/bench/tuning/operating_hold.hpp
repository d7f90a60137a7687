#pragma once
// One constant-rate hold of the gyro as a gyro (issue 28 §3): the table at a set rate, the
// electronics in the operating mode (whole-angle loops closed with the block they hold), the angle
// output read over whole turns of the wave, and the rate error Ω̂ − Ω against the table's measured
// rate: its bias and its harmonics in the wave angle (analysis::FitRateErrorHarmonics).
//
//   table → rate, stable → gyro Configure(whole angle) → Excite → WaitReady → Release →
//   angle output read for the hold, the table's angle and rate read every poll period (its Ω,
//   as a run's: bench/capture/run_omega.hpp) → gyro Stop.
//
// The table is left turning at the hold's rate (the next hold sets its own; the caller stops it).
// On any failure or a stop request the gyro is stopped and the result says why; the table is the
// caller's to stop (TuneUnit does, on every path).
//
// Units: rad/s, rad, s in the unit's frame (the table's rate × the unit's axis sign + the Earth
// rate on its axis). Not real-time; the calling thread owns the unit's gyro and the table.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "hrgbench/analysis/rate_error_harmonics.hpp"
#include "hrgbench/bench/sequencer/sequencer.hpp"
#include "hrgbench/hw/gyro_electronics.hpp"
#include "hrgbench/hw/operating_gyro.hpp"
#include "hrgbench/hw/rate_table.hpp"

namespace hrgbench::bench {

struct OperatingHoldPlan {
  double omega_rad_s = 0.3;  // the table's rate in the unit's frame, without the Earth rate
  // How long: whole turns of 2θ at the rate the block's angular gain gives (2π / (4·δ2·|Ω|) s a
  // turn of 2θ); at Ω = 0, or when > 0, `duration_s` instead.
  double turns = 2.0;
  double duration_s = 0.0;
  double angular_gain = 0.3;  // δ2 the turns are counted with (the block's)
  std::uint32_t sample_rate_hz = 1000;
  hw::WaveState wave{1.0, 0.0, 0.0};
  std::size_t window_samples = 100;  // the harmonics fit's window
  int harmonics = 2;  // of the rate error in 2θ, 1 … 8; 0: no fit (a zero-rate hold: no turn)
  hw::StableCriteria stable;       // tolerance, dwell, poll period (its timeout: settle_timeout_s)
  double settle_timeout_s = 60.0;  // the table at its rate within this, or the hold fails
  double ready_timeout_s = 30.0;
  double poll_period_s = 0.02;  // the table's status and angle, read between sample reads
  // The bounds a plan is refused beyond (no hold runs): the longest hold and the most samples.
  static constexpr double kMaxDurationS = 3600.0;
  static constexpr std::size_t kMaxSamples = 20'000'000;
};

struct OperatingHold {
  bool ok = false;
  std::string why;               // when not ok: the step and what failed
  double omega_set_rad_s = 0.0;  // the plan's, unit frame, without the Earth rate
  double omega_rad_s = 0.0;      // measured: the table's mean × axis sign + Earth rate
  double omega_std_error_rad_s = 0.0;
  std::string omega_source;  // "angle" or "rate" (bench/capture/run_omega.hpp)
  double duration_s = 0.0;
  std::size_t samples = 0;
  std::uint64_t sequence_gaps = 0;   // the stream's breaks during the hold (none expected)
  analysis::RateErrorHarmonics fit;  // Ω̂ − Ω against the wave angle
  // What the electronics reported of their loops over the hold (their worst energy error and
  // quadrature ratio: a verification is only as good as its loops' lock; none from electronics
  // that do not report them).
  hw::OperatingLoopsRecord loops;
  // The samples' rate error and unwrapped electrical wave angle (for the report's figure and the
  // Allan deviation of a zero-rate hold); the rate of sample k is over the period ending at it.
  std::vector<double> rate_error_rad_s;
  std::vector<double> wave_angle_rad;
};

// Runs one hold on unit `unit` of `hardware` (its gyro and its `operating` interface must be set).
// `earth_rate_rad_s`: the Earth-rate component on the table's axis (the site's). `stop`: when it
// turns non-zero (the program's interrupt count, as RunnerOptions::interrupts) the hold ends at
// once with ok = false ("stopped").
OperatingHold RunOperatingHold(const BenchHardware& hardware, const UnitHardware& unit,
                               const OperatingHoldPlan& plan, double earth_rate_rad_s,
                               const std::atomic<int>* stop = nullptr);

}  // namespace hrgbench::bench
