#pragma once
// CarrierElectronics: what the gyro's electronics do with the two converter streams — I/Q
// demodulation against the reference oscillator (u_c = 2·LPF[s_c·e^{−iψ}], the convention of
// estimator/physical_parameters.hpp, so x1 = Re u1, x2 = Im u1, ...), the Butterworth low-pass,
// decimation to the protocol's output rate (every `decimation`-th filtered sample, starting with
// the release sample), the tracking PLL's correction once per output sample, and the protocol's
// quantisation (gyro_can::QuantiseY, the sample frames' LSB).
//
// At release the demodulator has been running on the held wave: the filters hold the steady state
// of the held wave's demodulated value, and the reference is locked to the wave (phase 0).
//
// Threads: one thread. Real-time: Push() is allocation-free and noexcept.

#include <string>

#include "hrgbench/estimator/parameters.hpp"
#include "sim/butterworth_low_pass.hpp"
#include "sim/reference_oscillator.hpp"

namespace hrgbench::drivers::sim {

struct CarrierElectronicsOptions {
  ReferenceOptions reference;
  int filter_order = 4;             // Butterworth, even, 2…8
  double filter_cutoff_hz = 200.0;  // −3 dB; passes the slow signal (≤ a few Hz), rejects 2·f0
  bool quantise = true;             // the wire's LSB (off: the y before the protocol)

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
  const ReferenceOscillator& reference() const noexcept { return reference_; }
  int decimation() const noexcept { return decimation_; }

 private:
  CarrierElectronicsOptions options_;
  double output_period_s_;
  int decimation_;
  int phase_ = 0;  // samples since the last output
  ReferenceOscillator reference_;
  ButterworthLowPass filter_;
};

}  // namespace hrgbench::drivers::sim
