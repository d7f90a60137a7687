#pragma once
// CarrierElectronics: what the gyro's electronics do with the two converter streams — I/Q
// demodulation against the reference oscillator (u_c = 2·LPF[s_c·e^{−iψ}], the convention of
// estimator/physical_parameters.hpp, so x1 = Re u1, x2 = Im u1, ...), the Butterworth low-pass,
// decimation to the protocol's output rate (every `decimation`-th filtered sample, starting with
// the release sample), the tracking PLL's correction once per output sample, and the protocol's
// quantisation (gyro_can::QuantiseY, the sample frames' LSB).
//
// The I/Q sign convention (estimator/iq_convention.hpp) is the electronics' choice: "minus-sine"
// (the model's, the default) or "plus-sine" (y_Q = +2·LPF[s·sin ψ]), which outputs the complex
// conjugate of each channel, as such electronics do; its reported phase is then −χ, the angle that
// turns ITS (I, Q) back (the host's UndoReferencePhase turns by +reported), so that the host needs
// to know nothing about the convention to undo a tracking reference, and the record's declared
// convention alone says how to read the samples.
//
// At release the demodulator has been running on the held wave: the filters hold the steady state
// of the held wave's demodulated value, and the reference is locked to the wave (phase 0).
//
// What the electronics report about their reference (reported_phase_rad()): with each output
// sample, the reference's phase χ = ψ − 2π·f_lock·t relative to the reference locked at release,
// as seen through the output filter, i.e. χ at t − τg (τg the filter's DC group delay; χ is
// linear between output samples, so the value is interpolated exactly from the χ of past output
// samples, and is 0 before release, when the reference was locked). For a slow χ,
// u_c ≈ e^{−iχ(t−τg)}·u_c(reference kept locked): the bench undoes a tracking reference by turning
// each channel's (I, Q) back by χ (estimator/reference_phase.hpp). A free-running reference
// reports 2π·offset·t. A group delay above kPhaseHistory output periods is clamped to it.
//
// Threads: one thread. Real-time: Push() is allocation-free and noexcept.

#include <string>

#include "hrgbench/estimator/iq_convention.hpp"
#include "hrgbench/estimator/parameters.hpp"
#include "sim/butterworth_low_pass.hpp"
#include "sim/reference_oscillator.hpp"

namespace hrgbench::drivers::sim {

struct CarrierElectronicsOptions {
  ReferenceOptions reference;
  int filter_order = 4;             // Butterworth, even, 2…8
  double filter_cutoff_hz = 200.0;  // −3 dB; passes the slow signal (≤ a few Hz), rejects 2·f0
  bool quantise = true;             // the wire's LSB (off: the y before the protocol)
  // The electronics report their reference's phase (frame ReferencePhase, every 5th sample); false:
  // older electronics that do not (the host cannot undo a tracking reference then).
  bool report_reference_phase = true;
  // The demodulation's sign convention (above).
  estimator::IqConvention iq_convention = estimator::IqConvention::kMinusSine;

  bool IsValid(std::string* why) const;
};

class CarrierElectronics {
 public:
  // `sample_rate_hz`: the converters' rate; every `decimation`-th sample is an output.
  CarrierElectronics(const CarrierElectronicsOptions& options, double sample_rate_hz,
                     int decimation);

  // At release: the reference locked to `wave_frequency_hz`, the filters settled on `held`.
  void Release(double wave_frequency_hz, const estimator::Observation& held) noexcept;

  // One converter sample of both channels. True when it completed an output sample (*y).
  bool Push(const Eigen::Vector2d& s, estimator::Observation* y) noexcept;

  double group_delay_s() const noexcept { return filter_.group_delay_s(); }
  // χ(t − τg) of the last output sample, rad (above).
  double reported_phase_rad() const noexcept { return reported_phase_rad_; }
  static constexpr int kPhaseHistory = 64;  // output samples of χ kept for the delay
  const ReferenceOscillator& reference() const noexcept { return reference_; }
  int decimation() const noexcept { return decimation_; }

 private:
  CarrierElectronicsOptions options_;
  double output_period_s_;
  int decimation_;
  int phase_ = 0;  // samples since the last output
  // χ at the last kPhaseHistory output samples (ring, newest at history_head_), and the delay.
  double history_[kPhaseHistory] = {};
  int history_head_ = 0;
  int delay_whole_ = 0;          // τg in output periods: whole part …
  double delay_fraction_ = 0.0;  // … and fraction
  double reported_phase_rad_ = 0.0;
  ReferenceOscillator reference_;
  ButterworthLowPass filter_;
};

}  // namespace hrgbench::drivers::sim
