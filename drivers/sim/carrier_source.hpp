#pragma once
// CarrierSource: physics = "carrier". The node's free-run samples from CarrierSimulation (the mode
// at its carrier, the pick-off channels, the demodulating electronics; carrier_simulation.hpp):
// the same frames and protocol, a physics the estimator does not share. The converters' noise of
// run r is seeded with seed + r; the housing temperature's ramp moves the mode's frequency.

#include "sim/carrier_simulation.hpp"
#include "sim/free_run_source.hpp"

namespace hrgbench::drivers::sim {

class CarrierSource final : public FreeRunSource {
 public:
  CarrierSource(const CarrierOptions& options, std::uint64_t seed);  // valid options

  void Release(const FreeRunStart& start) noexcept override;
  estimator::Observation Sample(std::uint64_t k, std::int64_t t_ns,
                                double omega_rad_s) noexcept override;
  // f(T) = f0·(1 + α·(T − T0)): what the PLL reports.
  double ReportedFrequencyHz(double temperature_c) const noexcept override;
  // χ(t − τg) of the last sample (CarrierElectronics::reported_phase_rad), when
  // options.electronics.report_reference_phase; NaN otherwise (older electronics).
  double ReportedReferencePhaseRad() const noexcept override;

  const CarrierSimulation& simulation() const noexcept { return simulation_; }

 private:
  CarrierSimulation simulation_;
  std::uint64_t seed_;
};

}  // namespace hrgbench::drivers::sim
