#pragma once
// CarrierSimulation: the carrier-level chain of one simulated gyro — CarrierResonator (the mode at
// its carrier, exact in time) → CarrierPickoff (two channels, their errors and noise, at the
// converter rate) → CarrierElectronics (reference, I/Q demodulation, Butterworth, decimation,
// quantisation) — producing the y samples the gyro streams, one output sample per Next().
//
// Time: output sample k of a run is at t = k/output_rate after release (k = 0 is the release
// instant itself, as the protocol's sample 0). The converters run at decimation × output rate.
// Temperature T(t) = T(release) + rate·t enters through f(T) = f0·(1 + α·(T − T0)). Under a ramp
// the transition is computed at each output period's ends and interpolated linearly per
// converter sample, so the stiffness changes (almost) continuously: held piecewise constant per
// output period, its steps would fall at the same carrier phase every period (1 kHz divides
// 5 kHz) and pump the wave parametrically instead of letting its amplitude follow ω^{−1/2}
// (estimator/frequency_drift_decay.hpp). Ω is held over each output period (the value passed to
// Next for the period that follows sample k); the transition is recomputed only when it changed.
//
// Truth: y ≈ c·(I + C(ξ))·exp(A(Ω, δ)·t)·x0 with (δ, ξ) = estimator::SlowModelSeenOnUnit(
// resonator, the pick-off's H, ω̇/ω): δ the resonator's turned into the model's frame by the
// pick-off's frame angle, ξ the pick-off's in that frame plus the split's second-order mixing,
// to the averaging error O((|A|/ω0)²), plus what the real chain adds and the slow model has no
// term for (drivers/sim/README.md).
//
// The operating mode (GyroSimNode's whole-angle run mode; docs/estimator/operating-mode.md): the
// electronics' command u = (u1 + i·u2, u3 + i·u4), a slow complex pair in the demodulated frame,
// is modulated onto their own reference and driven through forcers at the electrodes:
// f(t) = Re[P·e^{iψ(t)}], P = −2ω·F·u (ω the wave's frequency, F = I + B(ε) the forcers' complex
// gain in the electrode frame), which averages to the slow model's dx/dt = … + B0·F·u (B0 = i:
// q = Re[x·e^{iψ}] gives ẋ = −i·P/(2ω)). The force is held over each converter step at its
// mid-point phase (the DAC's zero-order hold, an equal gain sinc(ω·dt/2) on both forcers: 0.4 %
// at 5 kHz and 100 kHz, which the energy loop absorbs). The command's feed-through D (η) adds
// Re[(D·u)_c·e^{iψ}] to channel c's converter sample, so the demodulator shows D·u. The command is
// in the model's frame and the forcers act in the electrode frame, so in the model the forcers'
// gain is c·V(a)·F. The pick-off chain's common phase arg c (its delay at the carrier) would put
// the force that far off the velocity: the quadrature loop's frequency split would then carry a
// damping split q·sin(arg c) that turns with the wave, an angle-dependent drift (4.7e-5 rad/s RMS
// for 2 µs and a 0.2 mHz split). Every HRG's drive phase is trimmed at the factory so that the
// energy loop's force is in phase with the velocity: the electronics multiply the command by
// c̄/|c| (the drive trim), and the forcers' gain in the model frame is |c|·V(a)·F
// (forcer_gain_in_model_frame): the pick-off's frame angle acts as forcers turned from it (a bias,
// operating-mode.md law 5) — a real unit's, not a simulation artefact. Observe/Advance
// are the ControlledResonator's contract: Observe gives output sample k with the command held
// until then (its feed-through), Advance carries the oscillator over the period with the new one.
// Under a temperature ramp the operating mode holds f(T) per output period (at its mid-point).
//
// Threads: one thread. Real-time: Next() is allocation-free and noexcept; it costs decimation ×
// (a 4×4 and a 2×4 product, the mixer and the filter), ~20 ns per converter sample.

#include <complex>
#include <cstdint>
#include <optional>

#include "hrgbench/estimator/model.hpp"
#include "sim/carrier_electronics.hpp"
#include "sim/carrier_options.hpp"
#include "sim/carrier_pickoff.hpp"
#include "sim/carrier_resonator.hpp"

namespace hrgbench::drivers::sim {

struct CarrierRelease {
  estimator::Orbit orbit;                 // the commanded wave state at release
  double omega_rad_s = 0.0;               // Ω at release
  double output_rate_hz = 1000.0;         // the protocol's sample rate, > 0
  std::uint64_t seed = 1;                 // the converters' noise
  double temperature_c = 25.0;            // at release
  double temperature_rate_c_per_s = 0.0;  // linear ramp from release on
};

class CarrierSimulation {
 public:
  explicit CarrierSimulation(const CarrierOptions& options);  // options.IsValid() must hold

  void Release(const CarrierRelease& release) noexcept;
  // The next output sample (the first after Release is sample 0, at the release instant), with Ω
  // held at `omega_rad_s` from it to the next.
  estimator::Observation Next(double omega_rad_s) noexcept;

  // The operating mode (above). SetControl after each Release (it may rebuild the resonator), then
  // Observe and Advance in turn.
  void SetControl(const Eigen::Matrix2cd& forcer_gain, const Eigen::Matrix2cd& feed_through);
  // Output sample k, with Ω held at `omega_rad_s` over the period that follows it and `u_held` the
  // command applied now.
  estimator::Observation Observe(double omega_rad_s, const Eigen::Vector4d& u_held) noexcept;
  // The period after the sample Observe gave, with the command `u` held over it.
  void Advance(const Eigen::Vector4d& u) noexcept;
  // c·V(a)·F: the forcers' gain as the slow model's B(ε) sees it (above).
  Eigen::Matrix2cd forcer_gain_in_model_frame() const noexcept {
    return pickoff_.model_from_electrode() * DriveTrim() * forcer_gain_;
  }

  // The δ the slow model should find for the current release: the resonator's in the model's
  // frame (estimator/pickoff_frame.hpp), with δ1 moved by the release's temperature ramp
  // (estimator/frequency_drift_decay.hpp).
  estimator::Delta delta() const noexcept;
  // The ξ the slow model should find: the pick-off's own plus the frequency split's second-order
  // term (estimator/split_coriolis_mixing.hpp; 9e-9 at Δf = 0.2 mHz, 4.6e-5 at 1 Hz).
  estimator::Xi xi() const noexcept;
  const estimator::Xi& pickoff_xi() const noexcept { return pickoff_.xi(); }  // the pick-off's
  // A wave's slow variables in the electrode frame → the slow model's state (CarrierPickoff).
  estimator::State ModelState(const estimator::State& x) const noexcept {
    return pickoff_.ModelState(x);
  }
  std::uint64_t samples() const noexcept { return k_; }  // output samples this run
  int decimation() const noexcept { return decimation_; }
  double converter_rate_hz() const noexcept { return decimation_ * release_.output_rate_hz; }
  double group_delay_s() const noexcept;
  const CarrierOptions& options() const noexcept { return options_; }
  const CarrierResonator& resonator() const noexcept { return *resonator_; }
  const CarrierElectronics& electronics() const noexcept { return *electronics_; }

 private:
  double FrequencyScale(double t_s) const noexcept;
  // c̄/|c|, the drive phase trim (above).
  std::complex<double> DriveTrim() const noexcept {
    return std::conj(pickoff_.common()) / std::abs(pickoff_.common());
  }

  CarrierOptions options_;
  CarrierPickoff pickoff_;
  std::optional<CarrierResonator> resonator_;
  std::optional<CarrierElectronics> electronics_;
  CarrierRelease release_;
  int decimation_ = 1;
  std::uint64_t k_ = 0;
  // The operating mode: the forcers, the feed-through, the reference's e^{−iψ} at the converter
  // sample Observe pushed (the first step of Advance's period is taken at it).
  Eigen::Matrix2cd forcer_gain_ = Eigen::Matrix2cd::Identity();
  Eigen::Matrix2cd feed_through_ = Eigen::Matrix2cd::Zero();
  std::complex<double> observed_phasor_{1.0, 0.0};
  // Under a temperature ramp: the transition at the start of the current output period (the end of
  // the last one), for the per-converter-sample interpolation in Next.
  Eigen::Matrix4d ramp_start_transition_ = Eigen::Matrix4d::Identity();
  bool ramp_start_valid_ = false;
};

}  // namespace hrgbench::drivers::sim
