// The simulator's side of the carrier table (carrier_config.hpp): the mapping only; the reading,
// defaults and bounds are the config layer's.

#include "sim/carrier_config.hpp"

#include <utility>

namespace hrgbench::drivers::sim {

CarrierOptions CarrierOptionsFrom(const bench::SimulatedCarrierConfig& c, CarrierOptions o) {
  o.resonator = c.resonator;
  o.frequency_temperature_coefficient_per_c = c.frequency_temperature_coefficient_per_c;
  o.reference_temperature_c = c.reference_temperature_c;
  o.pickoff.errors = c.pickoff;
  o.pickoff.common_gain = c.common_gain;
  o.pickoff.common_delay_s = c.common_delay_s;
  o.pickoff.white_noise_std = c.white_noise_std;
  o.pickoff.coloured_noise_std = c.coloured_noise_std;
  o.pickoff.coloured_noise_time_s = c.coloured_noise_time_s;
  o.sample_rate_hz = c.sample_rate_hz;
  o.electronics.reference.mode =
      c.tracking_reference ? ReferenceMode::kTracking : ReferenceMode::kFreeRunning;
  o.electronics.reference.offset_hz = c.reference_offset_hz;
  o.electronics.reference.pll_bandwidth_hz = c.pll_bandwidth_hz;
  o.electronics.filter_order = static_cast<int>(c.filter_order);
  o.electronics.filter_cutoff_hz = c.filter_cutoff_hz;
  o.electronics.report_reference_phase = c.report_reference_phase;
  o.electronics.iq_convention = c.iq_convention;
  return o;
}

std::expected<void, config_file::ConfigError> ReadCarrierTable(config_file::TableReader& reader,
                                                               CarrierOptions* options) {
  auto config = bench::ReadSimulatedCarrier(reader);
  if (!config) return std::unexpected(std::move(config).error());
  *options = CarrierOptionsFrom(*config, std::move(*options));
  return {};
}

}  // namespace hrgbench::drivers::sim
