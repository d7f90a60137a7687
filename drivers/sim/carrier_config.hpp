#pragma once
// The [carrier] table of hrg-gyro-sim's config file (gyro_sim_config.hpp), read into CarrierOptions
// with the project's strict reader: every key optional (absent = the in-class default), checked
// at its key against the bounds below, unknown keys are errors, and keys that do not apply to the
// chosen reference (reference_offset_hz with "tracking", pll_bandwidth_hz with "free-running") are
// errors too. The simulated station's [simulated.carrier] table (src/config/station_loader)
// has the same keys and bounds. Key by key: drivers/sim/README.md.
//
//   frequency_hz, decay_time_s, damping_anisotropy_per_s, damping_axis_rad, frequency_split_hz,
//   frequency_axis_rad, angular_gain                                     the mode
//   frequency_temperature_coefficient_per_c, reference_temperature_c       f(T)
//   gain_ratio, phase_mismatch_rad, cross_talk, electrode_angle_error_rad,
//   common_gain, common_delay_s                                            the pick-off path
//   white_noise_std, coloured_noise_std, coloured_noise_time_s, sample_rate_hz   the converters
//   reference ("free-running" | "tracking"), reference_offset_hz, pll_bandwidth_hz,
//   filter_order, filter_cutoff_hz, report_reference_phase                 the electronics

#include <expected>

#include "hrgbench/config/config_error.hpp"
#include "hrgbench/config/toml_reader.hpp"
#include "sim/carrier_options.hpp"

namespace hrgbench::drivers::sim {

std::expected<void, config_file::ConfigError> ReadCarrierTable(config_file::TableReader& reader,
                                                               CarrierOptions* options);

}  // namespace hrgbench::drivers::sim
