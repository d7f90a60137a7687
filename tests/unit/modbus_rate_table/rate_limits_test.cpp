#include "modbus_rate_table/rate_limits.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "modbus_rate_table/modbus_config.hpp"

namespace hrgbench::drivers::modbus_rate_table {
namespace {

TEST(RateLimits, RateWithinLimitPasses) {
  const RateLimits limits{.max_rate_rad_s = 2.0, .max_accel_rad_s2 = 1.0};
  EXPECT_TRUE(CheckRate(limits, 2.0));
  EXPECT_TRUE(CheckRate(limits, -2.0));
  EXPECT_TRUE(CheckRate(limits, 0.0));
}

TEST(RateLimits, RateBeyondLimitNamesLimitAndValue) {
  const RateLimits limits{.max_rate_rad_s = 2.0, .max_accel_rad_s2 = 1.0};
  const auto r = CheckRate(limits, -2.5);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, hw::RateTableErrorCode::kLimitExceeded);
  EXPECT_NE(r.error().message.find("max_rate_rad_s"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("-2.5"), std::string::npos) << r.error().message;
  EXPECT_FALSE(CheckRate(limits, std::nan("")));
  EXPECT_FALSE(CheckRate(limits, INFINITY));
}

TEST(RateLimits, AccelerationMustBePositiveAndWithinLimit) {
  const RateLimits limits{.max_rate_rad_s = 2.0, .max_accel_rad_s2 = 1.0};
  EXPECT_TRUE(CheckAcceleration(limits, 1.0));
  EXPECT_FALSE(CheckAcceleration(limits, 0.0));
  EXPECT_FALSE(CheckAcceleration(limits, -0.5));
  const auto r = CheckAcceleration(limits, 3.0);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("max_accel_rad_s2"), std::string::npos);
  EXPECT_NE(r.error().message.find('3'), std::string::npos);
}

TEST(ModbusConfig, DefaultsAreValidAndBadFieldsAreNamed) {
  std::string why;
  ModbusRateTableConfig config;
  EXPECT_TRUE(config.IsValid(&why)) << why;
  config.heartbeat_period_ms = 800;  // more than half the 1000 ms watchdog
  EXPECT_FALSE(config.IsValid(&why));
  EXPECT_NE(why.find("heartbeat_period_ms"), std::string::npos) << why;
  config = {};
  config.accel_limit_rad_s2 = 100.0;  // beyond the software limit
  EXPECT_FALSE(config.IsValid(&why));
  EXPECT_NE(why.find("accel_limit_rad_s2"), std::string::npos) << why;
  config = {};
  config.transport = ModbusTransport::kRtu;
  config.parity = 'X';
  EXPECT_FALSE(config.IsValid(&why));
  EXPECT_NE(why.find("parity"), std::string::npos) << why;
}

}  // namespace
}  // namespace hrgbench::drivers::modbus_rate_table
