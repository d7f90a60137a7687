#pragma once
// Options of the carrier-level simulated resonator and electronics (physics = "carrier"): the
// physical parameters of the mode and the pick-off path (estimator/physical_parameters.hpp), the
// temperature dependence of the frequency, the converters and the electronics. Plain data with
// in-class defaults; read from the [carrier] table of hrg-gyro-sim's config file
// (gyro_sim_config.hpp) and from a simulated station's [simulated.carrier] table
// (bench_configs/README.md). The bounds below are IsValid's; the config readers check them at
// their keys.

#include <string>

#include "hrgbench/estimator/physical_parameters.hpp"
#include "sim/carrier_electronics.hpp"
#include "sim/carrier_pickoff.hpp"

namespace hrgbench::drivers::sim {

// Bounds (IsValid and the config files).
inline constexpr double kMinCarrierSampleRateHz = 1000.0;  // converter rate
inline constexpr double kMaxCarrierSampleRateHz = 10.0e6;
inline constexpr double kMinSamplesPerCarrierPeriod = 4.0;  // rate ≥ 4·f0: 2·f0 below Nyquist
inline constexpr double kMaxCutoffOverCarrier = 0.25;       // filter cutoff ≤ f0/4

struct CarrierOptions {
  // The working mode. Defaults: a 5 kHz hemisphere, τ = 1000 s (Q ≈ 1.6e7), δ2 = 0.3.
  estimator::ResonatorParameters resonator;
  // f(T) = f0·(1 + α·(T − T0)); fused silica's α is of order +1e-5…1e-4 per °C. 0 = no drift.
  double frequency_temperature_coefficient_per_c = 0.0;  // α
  double reference_temperature_c = 25.0;                 // T0, where f = f0

  CarrierPickoffOptions pickoff;
  // The converters' rate. The chain runs at the multiple of the output rate nearest to it
  // (decimation = round(rate / output rate) ≥ 1).
  double sample_rate_hz = 100000.0;
  CarrierElectronicsOptions electronics;

  bool IsValid(std::string* why) const;
};

}  // namespace hrgbench::drivers::sim
