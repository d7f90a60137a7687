#pragma once
// ReferenceOscillator: the demodulator's reference (a numerically controlled oscillator at the
// converter rate). Before release the excitation loop has phase-locked it to the wave: at release
// its phase is the wave's (0) and its frequency the wave's. After release either
//   - kFreeRunning: it keeps that frequency plus a settable offset (a reference that drifts off the
//     wave: the demodulated signal turns at the offset, a common phase ramp), or
//   - kTracking: a type-2 PLL (PI on the phase, ζ = 1/√2, natural frequency 2π·pll_bandwidth_hz)
//     follows the wave's phase, measured once per output sample on the filtered signal as
//     ½·arg(u1² + u2²) (the orbit's phase φ whatever the wave angle: u1² + u2² = e^{2iφ}(a² − b²)).
//
// Phase is kept as a block start plus n·increment, re-synchronised every 256 samples, so 1e7
// samples carry no accumulated rounding (the phasor is rotated between re-syncs).
//
// Threads: one thread. Real-time: Next() and Correct() are allocation-free and noexcept.

#include <complex>
#include <string>

namespace hrgbench::drivers::sim {

enum class ReferenceMode { kFreeRunning, kTracking };

struct ReferenceOptions {
  ReferenceMode mode = ReferenceMode::kFreeRunning;
  double offset_hz = 0.0;         // kFreeRunning: reference − wave frequency after release
  double pll_bandwidth_hz = 2.0;  // kTracking: natural frequency of the loop, Hz

  bool IsValid(std::string* why) const;
};

class ReferenceOscillator {
 public:
  ReferenceOscillator(const ReferenceOptions& options, double sample_rate_hz);

  // Locked to the wave at release: phase 0, frequency = the wave's (+ offset when free-running).
  void Lock(double wave_frequency_hz) noexcept;

  // e^{−iψ} at the current sample, then ψ advances by one sample.
  std::complex<double> Next() noexcept {
    const std::complex<double> now = phasor_;
    if (++count_ == kResync) {
      Resync();
    } else {
      phasor_ *= rotation_;
    }
    return now;
  }

  // e^{−iψ} at the current sample, without advancing (what Next() will return).
  std::complex<double> current() const noexcept { return phasor_; }

  // kTracking: the wave's phase relative to the reference (rad), once per output period.
  void Correct(double phase_error_rad, double period_s) noexcept;

  double frequency_hz() const noexcept;  // now
  double phase_rad() const noexcept;     // ψ − 2π·(lock frequency)·t, accumulated correction

 private:
  static constexpr int kResync = 256;
  void Resync() noexcept;
  void SetIncrement(double frequency_rad_s) noexcept;

  ReferenceOptions options_;
  double sample_rate_hz_;
  double lock_rad_s_ = 0.0;      // the wave's frequency at release
  double current_rad_s_ = 0.0;   // NCO frequency now
  double integral_rad_s_ = 0.0;  // PLL integrator
  double block_phase_ = 0.0;     // ψ at the last re-sync, reduced to [0, 2π)
  double increment_ = 0.0;       // ψ per sample
  int count_ = 0;                // samples since the last re-sync
  double correction_ = 0.0;      // accumulated ψ − lock·t
  std::complex<double> phasor_{1.0, 0.0};
  std::complex<double> rotation_{1.0, 0.0};
};

}  // namespace hrgbench::drivers::sim
