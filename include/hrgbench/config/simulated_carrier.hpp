#pragma once
// The carrier-level simulated resonator, pick-off path and electronics as a config file declares
// them: a simulated station's [simulated.carrier] table and hrg-gyro-sim's [carrier] table have the
// same keys, defaults and bounds, so they are one reader (this one), and drivers/sim maps the
// result onto its CarrierOptions (drivers/sim/carrier_config.hpp). Key by key:
// drivers/sim/README.md.
//
//   frequency_hz, decay_time_s, damping_anisotropy_per_s, damping_axis_rad, frequency_split_hz,
//   frequency_axis_rad, angular_gain                                     the mode
//   frequency_temperature_coefficient_per_c, reference_temperature_c       f(T)
//   gain_ratio, phase_mismatch_rad, cross_talk, electrode_angle_error_rad,
//   common_gain, common_delay_s                                            the pick-off path
//   white_noise_std, coloured_noise_std, coloured_noise_time_s, sample_rate_hz   the converters
//   reference ("free-running" | "tracking"), reference_offset_hz, pll_bandwidth_hz,
//   filter_order, filter_cutoff_hz, report_reference_phase, iq_convention  the electronics
//
// Every key is optional (absent: the default below), checked at its key; the cross-field rules
// (sample_rate_hz >= 4 frequency_hz, filter_cutoff_hz <= frequency_hz / 4, even filter_order,
// frequency_split_hz < frequency_hz) are reported at the later key; keys of the other reference
// mode and unknown keys are errors. Part of hrgbench_config_file, so a driver can read it.

#include <cstdint>
#include <expected>

#include "hrgbench/config/config_error.hpp"
#include "hrgbench/config/toml_reader.hpp"
#include "hrgbench/estimator/iq_convention.hpp"
#include "hrgbench/estimator/physical_parameters.hpp"

namespace hrgbench::bench {

struct SimulatedCarrierConfig {
  estimator::ResonatorParameters resonator;  // frequency_hz ... angular_gain
  double frequency_temperature_coefficient_per_c = 0.0;
  double reference_temperature_c = 25.0;
  estimator::PickoffParameters pickoff;  // gain_ratio, phase_mismatch_rad, cross_talk, ...
  double common_gain = 1.0;
  double common_delay_s = 0.0;
  double white_noise_std = 0.0;
  double coloured_noise_std = 0.0;
  double coloured_noise_time_s = 1e-3;
  double sample_rate_hz = 100000.0;
  bool tracking_reference = false;  // reference = "tracking" (else "free-running")
  double reference_offset_hz = 0.0;
  double pll_bandwidth_hz = 2.0;
  std::int64_t filter_order = 4;
  double filter_cutoff_hz = 200.0;
  bool report_reference_phase = true;  // the electronics send their reference phase (0x103)
  // The demodulation's sign convention (estimator/iq_convention.hpp).
  estimator::IqConvention iq_convention = estimator::IqConvention::kMinusSine;
};

std::expected<SimulatedCarrierConfig, config_file::ConfigError> ReadSimulatedCarrier(
    config_file::TableReader& reader);

}  // namespace hrgbench::bench
