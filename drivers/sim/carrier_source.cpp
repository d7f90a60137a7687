#include "sim/carrier_source.hpp"

#include <limits>

namespace hrgbench::drivers::sim {

CarrierSource::CarrierSource(const CarrierOptions& options, std::uint64_t seed)
    : simulation_(options), seed_(seed) {}

void CarrierSource::Release(const FreeRunStart& start) noexcept {
  simulation_.Release({start.orbit, start.omega_rad_s, start.sample_rate_hz,
                       seed_ + start.run_index, start.temperature_c,
                       start.temperature_rate_c_per_s});
}

estimator::Observation CarrierSource::Sample(std::uint64_t /*k*/, std::int64_t /*t_ns*/,
                                             double omega_rad_s) noexcept {
  // The node asks for every sample in order, k = 0, 1, ...: the simulation's own count.
  return simulation_.Next(omega_rad_s);
}

double CarrierSource::ReportedReferencePhaseRad() const noexcept {
  if (!simulation_.options().electronics.report_reference_phase) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return simulation_.electronics().reported_phase_rad();
}

double CarrierSource::ReportedFrequencyHz(double temperature_c) const noexcept {
  const CarrierOptions& o = simulation_.options();
  return o.resonator.frequency_hz * (1.0 + o.frequency_temperature_coefficient_per_c *
                                               (temperature_c - o.reference_temperature_c));
}

}  // namespace hrgbench::drivers::sim
