// Reader of the [carrier] table (carrier_config.hpp). The bounds are wide enough for any real
// resonator and chain and narrow enough that a unit typo (Hz for kHz, µs for s) is caught; the
// cross-field rules (rate ≥ 4·f0, cutoff ≤ f0/4, split < f0) are checked at the later key.

#include "sim/carrier_config.hpp"

#include <numbers>
#include <string>

#include "hrgbench/hw/gyro_electronics.hpp"

namespace hrgbench::drivers::sim {
namespace {

using namespace config_file;  // NOLINT(google-build-using-namespace): the loader's vocabulary

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr Range kFrequency{0.0, hw::kMaxReportedResonantFrequencyHz, false,
                           "in (0, 16777.215] (the status field's range)"};
constexpr Range kDecayTime{0.0, 1e7, false, "in (0, 1e7] s"};
constexpr Range kDampingAnisotropy{0.0, 1.0, true, "in [0, 1] 1/s"};
constexpr Range kAxis{-kTwoPi, kTwoPi, true, "in [-2*pi, 2*pi] rad"};
constexpr Range kSplit{0.0, 100.0, true, "in [0, 100] Hz"};
constexpr Range kAngularGain{-1.0, 1.0, true, "in [-1, 1]"};
constexpr Range kTemperatureCoefficient{-1e-2, 1e-2, true, "in [-1e-2, 1e-2] per degC"};
constexpr Range kTemperature{-327.67, 327.67, true, "in [-327.67, 327.67]"};
// |ξ| < 1/4 for the slow physics; these keep the mapped ξ of the same size.
constexpr Range kGainRatio{0.5, 2.0, true, "in [0.5, 2]"};
constexpr Range kPhase{-0.5, 0.5, true, "in [-0.5, 0.5] rad"};
constexpr Range kCrossTalk{-0.25, 0.25, true, "in [-0.25, 0.25]"};
constexpr Range kCommonGain{0.0, 100.0, false, "in (0, 100]"};
constexpr Range kCommonDelay{0.0, 1e-3, true, "in [0, 1e-3] s"};
constexpr Range kNoise{0.0, 1.0, true, "in [0, 1]"};
constexpr Range kNoiseTime{0.0, 10.0, false, "in (0, 10] s"};
constexpr Range kSampleRate{kMinCarrierSampleRateHz, kMaxCarrierSampleRateHz, true,
                            "in [1e3, 1e7] Hz"};
constexpr Range kOffset{-100.0, 100.0, true, "in [-100, 100] Hz"};
constexpr Range kBandwidth{0.0, 100.0, false, "in (0, 100] Hz"};

std::expected<void, ConfigError> Number(TableReader& reader, std::string_view key,
                                        const Range& range, double* out) {
  HRG_TRY(v, OptionalNumber(reader, key, range, *out));
  *out = *v;
  return {};
}

// A value that must also respect another key's value: reported at `key` (or as missing if absent,
// i.e. the default clashes).
std::expected<void, ConfigError> Check(TableReader& reader, std::string_view key, bool ok,
                                       const std::string& message) {
  if (ok) return {};
  const toml::node* node = reader.table().get(key);
  if (node == nullptr) return std::unexpected(reader.Missing(key, message));
  return std::unexpected(reader.Error(*node, key, "out of range: " + message));
}

}  // namespace

std::expected<void, ConfigError> ReadCarrierTable(TableReader& reader, CarrierOptions* o) {
  estimator::ResonatorParameters& r = o->resonator;
  HRG_TRY(f0, Number(reader, "frequency_hz", kFrequency, &r.frequency_hz));
  HRG_TRY(tau, Number(reader, "decay_time_s", kDecayTime, &r.decay_time_s));
  HRG_TRY(dtau, Number(reader, "damping_anisotropy_per_s", kDampingAnisotropy,
                       &r.damping_anisotropy_per_s));
  HRG_TRY(dtau_axis, Number(reader, "damping_axis_rad", kAxis, &r.damping_axis_rad));
  HRG_TRY(split, Number(reader, "frequency_split_hz", kSplit, &r.frequency_split_hz));
  HRG_TRY(split_ok, Check(reader, "frequency_split_hz", r.frequency_split_hz < r.frequency_hz,
                          "must be < frequency_hz"));
  HRG_TRY(split_axis, Number(reader, "frequency_axis_rad", kAxis, &r.frequency_axis_rad));
  HRG_TRY(gain, Number(reader, "angular_gain", kAngularGain, &r.angular_gain));
  HRG_TRY(alpha, Number(reader, "frequency_temperature_coefficient_per_c", kTemperatureCoefficient,
                        &o->frequency_temperature_coefficient_per_c));
  HRG_TRY(t0, Number(reader, "reference_temperature_c", kTemperature, &o->reference_temperature_c));

  CarrierPickoffOptions& p = o->pickoff;
  HRG_TRY(ratio, Number(reader, "gain_ratio", kGainRatio, &p.errors.gain_ratio));
  HRG_TRY(phase, Number(reader, "phase_mismatch_rad", kPhase, &p.errors.phase_mismatch_rad));
  HRG_TRY(cross, Number(reader, "cross_talk", kCrossTalk, &p.errors.cross_talk));
  HRG_TRY(angle,
          Number(reader, "electrode_angle_error_rad", kPhase, &p.errors.electrode_angle_error_rad));
  HRG_TRY(common_gain, Number(reader, "common_gain", kCommonGain, &p.common_gain));
  HRG_TRY(common_delay, Number(reader, "common_delay_s", kCommonDelay, &p.common_delay_s));
  HRG_TRY(white, Number(reader, "white_noise_std", kNoise, &p.white_noise_std));
  HRG_TRY(coloured, Number(reader, "coloured_noise_std", kNoise, &p.coloured_noise_std));
  HRG_TRY(coloured_time,
          Number(reader, "coloured_noise_time_s", kNoiseTime, &p.coloured_noise_time_s));
  HRG_TRY(rate, Number(reader, "sample_rate_hz", kSampleRate, &o->sample_rate_hz));
  HRG_TRY(rate_ok, Check(reader, "sample_rate_hz",
                         o->sample_rate_hz >= kMinSamplesPerCarrierPeriod * r.frequency_hz,
                         "must be >= 4 * frequency_hz (" +
                             std::to_string(kMinSamplesPerCarrierPeriod * r.frequency_hz) +
                             "), so that the 2*f0 image is below Nyquist"));

  CarrierElectronicsOptions& e = o->electronics;
  HRG_TRY(mode, Choice(reader, "reference", {"free-running", "tracking"},
                       e.reference.mode == ReferenceMode::kFreeRunning ? 0 : 1));
  e.reference.mode = *mode == 0 ? ReferenceMode::kFreeRunning : ReferenceMode::kTracking;
  if (e.reference.mode == ReferenceMode::kFreeRunning) {
    HRG_TRY(offset, Number(reader, "reference_offset_hz", kOffset, &e.reference.offset_hz));
    HRG_CHECK(Forbid(reader, "pll_bandwidth_hz", "applies only to reference = \"tracking\""));
  } else {
    HRG_TRY(bandwidth,
            Number(reader, "pll_bandwidth_hz", kBandwidth, &e.reference.pll_bandwidth_hz));
    HRG_CHECK(
        Forbid(reader, "reference_offset_hz", "applies only to reference = \"free-running\""));
  }
  HRG_TRY(order, OptionalInteger(reader, "filter_order", 2, 8, e.filter_order));
  e.filter_order = static_cast<int>(*order);
  HRG_TRY(order_ok, Check(reader, "filter_order", e.filter_order % 2 == 0, "must be even"));
  HRG_TRY(cutoff, Number(reader, "filter_cutoff_hz", kPositive, &e.filter_cutoff_hz));
  HRG_TRY(cutoff_ok, Check(reader, "filter_cutoff_hz",
                           e.filter_cutoff_hz <= kMaxCutoffOverCarrier * r.frequency_hz,
                           "must be <= frequency_hz / 4 (" +
                               std::to_string(kMaxCutoffOverCarrier * r.frequency_hz) +
                               "), so that the 2*f0 image is rejected"));
  HRG_TRY(report, OptionalBool(reader, "report_reference_phase", e.report_reference_phase));
  e.report_reference_phase = *report;
  HRG_TRY(iq, Choice(reader, "iq_convention", {"minus-sine", "plus-sine"},
                     e.iq_convention == estimator::IqConvention::kPlusSine ? 1 : 0));
  e.iq_convention =
      *iq == 1 ? estimator::IqConvention::kPlusSine : estimator::IqConvention::kMinusSine;
  HRG_CHECK(reader.Unknown(
      "frequency_hz, decay_time_s, damping_anisotropy_per_s, damping_axis_rad, "
      "frequency_split_hz, frequency_axis_rad, angular_gain, "
      "frequency_temperature_coefficient_per_c, reference_temperature_c, gain_ratio, "
      "phase_mismatch_rad, cross_talk, electrode_angle_error_rad, common_gain, common_delay_s, "
      "white_noise_std, coloured_noise_std, coloured_noise_time_s, sample_rate_hz, reference, "
      "reference_offset_hz, pll_bandwidth_hz, filter_order, filter_cutoff_hz, "
      "report_reference_phase, iq_convention"));
  return {};
}

}  // namespace hrgbench::drivers::sim
