#pragma once
// FreeRunSource: where the simulated electronics (GyroSimNode) get the y samples of a free run —
// the physics behind the protocol. Two implementations, chosen by GyroSimOptions::physics:
//   SlowModelSource     (physics = "slow", the default): the estimator's own closed-form model,
//                       y = (I + C(ξ))·exp(A·t)·x0 + σ·n (slow_model_source.hpp);
//   CarrierSource       (physics = "carrier"): the 2-DOF resonator at its carrier, the pick-off
//                       channels and the demodulating electronics (carrier_source.hpp).
// The node owns one, calls Release at each release and Sample for each due sample, in order, and
// quantises what Sample returns onto the wire.
//
// Threads: the node's thread. Real-time: Release and Sample are noexcept and allocation-free.

#include <cstdint>
#include <limits>

#include "hrgbench/estimator/model.hpp"

namespace hrgbench::drivers::sim {

struct FreeRunStart {
  estimator::Orbit orbit;          // the commanded wave state (φ = 0)
  double omega_rad_s = 0.0;        // Ω at release
  double sample_rate_hz = 1000.0;  // the configured output rate
  std::uint64_t run_index = 0;     // 0-based count of releases (noise streams: seed + run_index)
  double temperature_c = 25.0;     // housing temperature at release
  double temperature_rate_c_per_s = 0.0;
};

class FreeRunSource {
 public:
  virtual ~FreeRunSource() = default;
  virtual void Release(const FreeRunStart& start) noexcept = 0;
  // Sample k (0 = the release instant), due t_ns after release; Ω now, held until the next sample.
  // y in amplitude units, before the wire's quantisation.
  virtual estimator::Observation Sample(std::uint64_t k, std::int64_t t_ns,
                                        double omega_rad_s) noexcept = 0;
  // The resonant frequency the electronics report in Status at housing temperature T, Hz.
  virtual double ReportedFrequencyHz(double temperature_c) const noexcept = 0;
  // The demodulation reference's phase χ the electronics report with the last sample (frame
  // ReferencePhase, drivers/gyro_can/README.md "Reference phase"), rad; NaN: not reported (the slow
  // model's ideal reference, or electronics without the report).
  virtual double ReportedReferencePhaseRad() const noexcept {
    return std::numeric_limits<double>::quiet_NaN();
  }
};

}  // namespace hrgbench::drivers::sim
