#pragma once
// Software limits: the bench's own ceiling on what it may command, checked BEFORE anything is sent,
// independent of (and normally tighter than) the table's hardware limits. Pure functions.

#include <expected>

#include "hrgbench/hw/rate_table.hpp"

namespace hrgbench::drivers::modbus_rate_table {

struct RateLimits {
  // The gyro's rated input range with margin; the paper's designs stay within +-1 rad/s.
  double max_rate_rad_s = 10.0;
  // Keeps the gyro's resonator and the cabling's slip ring within their specification.
  double max_accel_rad_s2 = 5.0;

  bool IsValid(std::string* why) const;
};

// kLimitExceeded naming the limit and the value when |rate| > max_rate_rad_s or rate is not finite.
std::expected<void, hw::RateTableError> CheckRate(const RateLimits& limits, double rate_rad_s);
// kLimitExceeded when accel is not finite, <= 0 or > max_accel_rad_s2.
std::expected<void, hw::RateTableError> CheckAcceleration(const RateLimits& limits,
                                                          double accel_rad_s2);

}  // namespace hrgbench::drivers::modbus_rate_table
