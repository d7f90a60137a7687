#include "sim/carrier_options.hpp"

#include <cmath>

namespace hrgbench::drivers::sim {

bool CarrierOptions::IsValid(std::string* why) const {
  const auto fail = [why](const std::string& message) {
    if (why != nullptr) *why = message;
    return false;
  };
  std::string part;
  if (!resonator.IsValid(&part)) return fail("resonator: " + part);
  if (!pickoff.IsValid(&part)) return fail("pickoff: " + part);
  if (!electronics.IsValid(&part)) return fail("electronics: " + part);
  if (!std::isfinite(frequency_temperature_coefficient_per_c) ||
      std::abs(frequency_temperature_coefficient_per_c) > 1e-2) {
    return fail("frequency_temperature_coefficient_per_c must be finite and within +-1e-2");
  }
  if (!std::isfinite(reference_temperature_c) || std::abs(reference_temperature_c) > 1000.0) {
    return fail("reference_temperature_c must be finite and within +-1000");
  }
  if (!(std::isfinite(sample_rate_hz) && sample_rate_hz >= kMinCarrierSampleRateHz &&
        sample_rate_hz <= kMaxCarrierSampleRateHz)) {
    return fail("sample_rate_hz must be in [1e3, 1e7]");
  }
  if (sample_rate_hz < kMinSamplesPerCarrierPeriod * resonator.frequency_hz) {
    return fail("sample_rate_hz must be >= 4 * frequency_hz (the 2*f0 image below Nyquist)");
  }
  if (electronics.filter_cutoff_hz > kMaxCutoffOverCarrier * resonator.frequency_hz) {
    return fail("filter_cutoff_hz must be <= frequency_hz / 4 (to reject the 2*f0 image)");
  }
  return true;
}

}  // namespace hrgbench::drivers::sim
