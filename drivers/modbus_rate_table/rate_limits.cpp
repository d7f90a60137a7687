#include "modbus_rate_table/rate_limits.hpp"

#include <cmath>

#include "hrgbench/hw/error_text.hpp"

namespace hrgbench::drivers::modbus_rate_table {

bool RateLimits::IsValid(std::string* why) const {
  if (!(std::isfinite(max_rate_rad_s) && max_rate_rad_s > 0.0)) {
    if (why != nullptr) *why = hw::ErrorText("max_rate_rad_s must be > 0, got ", max_rate_rad_s);
    return false;
  }
  if (!(std::isfinite(max_accel_rad_s2) && max_accel_rad_s2 > 0.0)) {
    if (why != nullptr)
      *why = hw::ErrorText("max_accel_rad_s2 must be > 0, got ", max_accel_rad_s2);
    return false;
  }
  return true;
}

std::expected<void, hw::RateTableError> CheckRate(const RateLimits& limits, double rate_rad_s) {
  if (!std::isfinite(rate_rad_s) || std::abs(rate_rad_s) > limits.max_rate_rad_s) {
    return std::unexpected(hw::RateTableError{
        hw::RateTableErrorCode::kLimitExceeded,
        hw::ErrorText("rate ", rate_rad_s, " rad/s is outside the software limit max_rate_rad_s = ",
                      limits.max_rate_rad_s, " rad/s")});
  }
  return {};
}

std::expected<void, hw::RateTableError> CheckAcceleration(const RateLimits& limits,
                                                          double accel_rad_s2) {
  if (!std::isfinite(accel_rad_s2) || accel_rad_s2 <= 0.0 ||
      accel_rad_s2 > limits.max_accel_rad_s2) {
    return std::unexpected(hw::RateTableError{
        hw::RateTableErrorCode::kLimitExceeded,
        hw::ErrorText("acceleration ", accel_rad_s2,
                      " rad/s^2 is outside the software limit max_accel_rad_s2 = ",
                      limits.max_accel_rad_s2, " rad/s^2 (and must be > 0)")});
  }
  return {};
}

}  // namespace hrgbench::drivers::modbus_rate_table
