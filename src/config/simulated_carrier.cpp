// The one reader of a simulated carrier table (simulated_carrier.hpp). The bounds are wide enough
// for any real resonator and chain and narrow enough that a unit typo (Hz for kHz, us for s) is
// caught; |xi| < 1/4 for the slow physics, and the pick-off bounds keep the mapped xi of that size.

#include "hrgbench/config/simulated_carrier.hpp"

#include <numbers>
#include <string>
#include <string_view>

#include "hrgbench/hw/gyro_electronics.hpp"

namespace hrgbench::bench {
namespace {

using namespace config_file;  // NOLINT(google-build-using-namespace): the loader's vocabulary

std::expected<void, ConfigError> Number(TableReader& reader, std::string_view key,
                                        const Range& range, double* out) {
  HRG_TRY(v, OptionalNumber(reader, key, range, *out));
  *out = *v;
  return {};
}

std::expected<void, ConfigError> CrossCheck(TableReader& reader, std::string_view key, bool ok,
                                            const std::string& message) {
  if (ok) return {};
  const toml::node* node = reader.table().get(key);
  if (node == nullptr) return std::unexpected(reader.Missing(key, message));
  return std::unexpected(reader.Error(*node, key, "out of range: " + message));
}

}  // namespace

std::expected<SimulatedCarrierConfig, ConfigError> ReadSimulatedCarrier(TableReader& reader) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  constexpr Range kAxis{-kTwoPi, kTwoPi, true, "in [-2*pi, 2*pi] rad"};
  constexpr Range kPhase{-0.5, 0.5, true, "in [-0.5, 0.5] rad"};
  constexpr Range kNoise{0.0, 1.0, true, "in [0, 1]"};
  SimulatedCarrierConfig c;
  estimator::ResonatorParameters& r = c.resonator;
  HRG_TRY(f0, Number(reader, "frequency_hz",
                     {0.0, hw::kMaxReportedResonantFrequencyHz, false,
                      "in (0, 16777.215] (the status field's range)"},
                     &r.frequency_hz));
  HRG_TRY(tau, Number(reader, "decay_time_s", {0.0, 1e7, false, "in (0, 1e7] s"}, &r.decay_time_s));
  HRG_TRY(dtau, Number(reader, "damping_anisotropy_per_s", {0.0, 1.0, true, "in [0, 1] 1/s"},
                       &r.damping_anisotropy_per_s));
  HRG_TRY(dtau_axis, Number(reader, "damping_axis_rad", kAxis, &r.damping_axis_rad));
  HRG_TRY(split, Number(reader, "frequency_split_hz", {0.0, 100.0, true, "in [0, 100] Hz"},
                        &r.frequency_split_hz));
  HRG_TRY(split_ok, CrossCheck(reader, "frequency_split_hz", r.frequency_split_hz < r.frequency_hz,
                               "must be < frequency_hz"));
  HRG_TRY(split_axis, Number(reader, "frequency_axis_rad", kAxis, &r.frequency_axis_rad));
  HRG_TRY(gain, Number(reader, "angular_gain", {-1.0, 1.0, true, "in [-1, 1]"}, &r.angular_gain));
  HRG_TRY(alpha, Number(reader, "frequency_temperature_coefficient_per_c",
                        {-1e-2, 1e-2, true, "in [-1e-2, 1e-2] per degC"},
                        &c.frequency_temperature_coefficient_per_c));
  HRG_TRY(t0, Number(reader, "reference_temperature_c",
                     {-327.67, 327.67, true, "in [-327.67, 327.67]"}, &c.reference_temperature_c));
  HRG_TRY(ratio,
          Number(reader, "gain_ratio", {0.5, 2.0, true, "in [0.5, 2]"}, &c.pickoff.gain_ratio));
  HRG_TRY(phase, Number(reader, "phase_mismatch_rad", kPhase, &c.pickoff.phase_mismatch_rad));
  HRG_TRY(cross, Number(reader, "cross_talk", {-0.25, 0.25, true, "in [-0.25, 0.25]"},
                        &c.pickoff.cross_talk));
  HRG_TRY(angle, Number(reader, "electrode_angle_error_rad", kPhase,
                        &c.pickoff.electrode_angle_error_rad));
  HRG_TRY(common_gain,
          Number(reader, "common_gain", {0.0, 100.0, false, "in (0, 100]"}, &c.common_gain));
  HRG_TRY(common_delay,
          Number(reader, "common_delay_s", {0.0, 1e-3, true, "in [0, 1e-3] s"}, &c.common_delay_s));
  HRG_TRY(white, Number(reader, "white_noise_std", kNoise, &c.white_noise_std));
  HRG_TRY(coloured, Number(reader, "coloured_noise_std", kNoise, &c.coloured_noise_std));
  HRG_TRY(coloured_time, Number(reader, "coloured_noise_time_s", {0.0, 10.0, false, "in (0, 10] s"},
                                &c.coloured_noise_time_s));
  HRG_TRY(rate, Number(reader, "sample_rate_hz", {1e3, 1e7, true, "in [1e3, 1e7] Hz"},
                       &c.sample_rate_hz));
  HRG_TRY(rate_ok,
          CrossCheck(reader, "sample_rate_hz", c.sample_rate_hz >= 4.0 * r.frequency_hz,
                     "must be >= 4 * frequency_hz (" + std::to_string(4.0 * r.frequency_hz) +
                         "), so that the 2*f0 image is below Nyquist"));
  HRG_TRY(mode, Choice(reader, "reference", {"free-running", "tracking"}, 0));
  c.tracking_reference = *mode == 1;
  if (!c.tracking_reference) {
    HRG_TRY(offset, Number(reader, "reference_offset_hz",
                           {-100.0, 100.0, true, "in [-100, 100] Hz"}, &c.reference_offset_hz));
    HRG_CHECK(Forbid(reader, "pll_bandwidth_hz", "applies only to reference = \"tracking\""));
  } else {
    HRG_TRY(bandwidth, Number(reader, "pll_bandwidth_hz", {0.0, 100.0, false, "in (0, 100] Hz"},
                              &c.pll_bandwidth_hz));
    HRG_CHECK(
        Forbid(reader, "reference_offset_hz", "applies only to reference = \"free-running\""));
  }
  HRG_TRY(order, OptionalInteger(reader, "filter_order", 2, 8, c.filter_order));
  c.filter_order = *order;
  HRG_TRY(order_ok, CrossCheck(reader, "filter_order", c.filter_order % 2 == 0, "must be even"));
  HRG_TRY(cutoff, Number(reader, "filter_cutoff_hz", kPositive, &c.filter_cutoff_hz));
  HRG_TRY(cutoff_ok,
          CrossCheck(reader, "filter_cutoff_hz", c.filter_cutoff_hz <= 0.25 * r.frequency_hz,
                     "must be <= frequency_hz / 4 (" + std::to_string(0.25 * r.frequency_hz) +
                         "), so that the 2*f0 image is rejected"));
  HRG_TRY(report, OptionalBool(reader, "report_reference_phase", c.report_reference_phase));
  c.report_reference_phase = *report;
  HRG_TRY(iq, Choice(reader, "iq_convention", {"minus-sine", "plus-sine"},
                     c.iq_convention == estimator::IqConvention::kPlusSine ? 1 : 0));
  c.iq_convention =
      *iq == 1 ? estimator::IqConvention::kPlusSine : estimator::IqConvention::kMinusSine;
  HRG_CHECK(reader.Unknown(
      "frequency_hz, decay_time_s, damping_anisotropy_per_s, damping_axis_rad, "
      "frequency_split_hz, frequency_axis_rad, angular_gain, "
      "frequency_temperature_coefficient_per_c, reference_temperature_c, gain_ratio, "
      "phase_mismatch_rad, cross_talk, electrode_angle_error_rad, common_gain, common_delay_s, "
      "white_noise_std, coloured_noise_std, coloured_noise_time_s, sample_rate_hz, reference, "
      "reference_offset_hz, pll_bandwidth_hz, filter_order, filter_cutoff_hz, "
      "report_reference_phase, iq_convention"));
  return c;
}

}  // namespace hrgbench::bench
