#include "sim/gyro_sim_options.hpp"

#include <cmath>
#include <sstream>

#include "hrgbench/hw/gyro_electronics.hpp"

namespace hrgbench::drivers::sim {

bool GyroSimOptions::IsValid(std::string* why) const {
  const auto fail = [why](const std::string& message) {
    if (why != nullptr) *why = message;
    return false;
  };
  if (node > gyro_can::kMaxNodeId) {
    return fail("node must be in 0.." + std::to_string(gyro_can::kMaxNodeId) + ", got " +
                std::to_string(node));
  }
  if (!delta.allFinite()) return fail("delta must be finite");
  if (!xi.allFinite() || xi.cwiseAbs().maxCoeff() >= kMaxAbsXi) {
    return fail("xi must be finite with |xi_i| < 0.25 (the distortion is a small perturbation)");
  }
  if (!std::isfinite(sigma) || sigma < 0) {
    std::ostringstream os;
    os << "sigma must be finite and >= 0, got " << sigma;
    return fail(os.str());
  }
  if (!std::isfinite(excite_time_s) || excite_time_s < 0 || excite_time_s > kMaxExciteTimeS) {
    return fail("excite_time_s must be in [0, 600]");
  }
  if (!std::isfinite(resonant_frequency_hz) || resonant_frequency_hz <= 0 ||
      resonant_frequency_hz > hw::kMaxReportedResonantFrequencyHz) {
    return fail("resonant_frequency_hz must be in (0, 16777.215] (the status field's range)");
  }
  if (!std::isfinite(temperature_drift_c_per_s) || std::abs(temperature_drift_c_per_s) > 10.0) {
    return fail("temperature_drift_c_per_s must be within +-10");
  }
  if (!std::isfinite(temperature_c) || std::abs(temperature_c) > kMaxAbsTemperatureC) {
    return fail("temperature_c must be within +-327.67");
  }
  if (physics == GyroPhysics::kCarrier) {
    std::string part;
    if (!carrier.IsValid(&part)) return fail("carrier: " + part);
    if (carrier.resonator.frequency_hz > hw::kMaxReportedResonantFrequencyHz) {
      return fail("carrier frequency_hz must be <= 16777.215 (the status field's range)");
    }
  }
  if (poll_period_ns <= 0 || poll_period_ns > 10'000'000) {
    return fail("poll_period_ns must be in (0, 10 ms]");
  }
  return true;
}

}  // namespace hrgbench::drivers::sim
