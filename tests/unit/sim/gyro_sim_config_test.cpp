// The hrg-gyro-sim TOML config: the shipped example loads, unknown keys and bad values are errors
// that name file, line, key and value (the project's ConfigError, as for the bench's configs).

#include "sim/gyro_sim_config.hpp"

#include <gtest/gtest.h>

namespace hrgbench::drivers::sim {
namespace {

TEST(GyroSimConfigTest, ShippedExampleLoads) {
  const auto config = LoadGyroSimConfig(HRGBENCH_SOURCE_DIR "/drivers/sim/gyro_sim.example.toml");
  ASSERT_TRUE(config.has_value()) << config.error().ToString();
  EXPECT_DOUBLE_EQ(config->options.delta(1), 0.3);
  EXPECT_DOUBLE_EQ(config->options.xi(0), 0.01);
  EXPECT_DOUBLE_EQ(config->options.sigma, 1e-4);
  EXPECT_EQ(config->omega.source, OmegaConfig::Source::kConstant);
  EXPECT_EQ(config->omega.modbus_port, 1502);
  EXPECT_EQ(config->options.faults.stall_after_samples, -1);
}

TEST(GyroSimConfigTest, FaultsAndOmegaAreRead) {
  const auto config = ParseGyroSimConfig(
      "[omega]\nsource = \"modbus\"\nmodbus_port = 1502\nearth_rate_rad_s = 7.3e-5\n"
      "[faults]\ndrop_every_nth_frame = 7\nno_reply = true\nfault_bits = 5\n",
      "sim.toml");
  ASSERT_TRUE(config.has_value()) << config.error().ToString();
  EXPECT_EQ(config->omega.source, OmegaConfig::Source::kModbus);
  EXPECT_DOUBLE_EQ(config->omega.earth_rate_rad_s, 7.3e-5);
  EXPECT_EQ(config->options.faults.drop_every_nth_frame, 7u);
  EXPECT_TRUE(config->options.faults.no_reply);
  EXPECT_EQ(config->options.faults.fault_bits, 5);
}

TEST(GyroSimConfigTest, ErrorsNameFileLineKeyAndValue) {
  const auto unknown = ParseGyroSimConfig("[model]\nsigma = 1e-4\nsigmaa = 2\n", "sim.toml");
  ASSERT_FALSE(unknown.has_value());
  EXPECT_EQ(
      unknown.error().ToString(),
      "sim.toml:3: key 'model.sigmaa' = 2: unknown key (allowed here: delta, xi, sigma, seed)");
  const auto wrong = ParseGyroSimConfig("[model]\ndelta = [1, 2]\n", "sim.toml");
  ASSERT_FALSE(wrong.has_value());
  EXPECT_NE(wrong.error().ToString().find("sim.toml:2: key 'model.delta'"), std::string::npos)
      << wrong.error().ToString();
  const auto range = ParseGyroSimConfig("[faults]\nfault_bits = 300\n", "sim.toml");
  ASSERT_FALSE(range.has_value());
  EXPECT_NE(range.error().ToString().find("sim.toml:2: key 'faults.fault_bits' = 300"),
            std::string::npos)
      << range.error().ToString();
  const auto table = ParseGyroSimConfig("[modle]\n", "sim.toml");
  ASSERT_FALSE(table.has_value());
  EXPECT_NE(table.error().ToString().find("unknown key"), std::string::npos);
  const auto invalid = ParseGyroSimConfig("[model]\nsigma = -1.0\n", "sim.toml");
  ASSERT_FALSE(invalid.has_value());
  EXPECT_NE(invalid.error().ToString().find("sigma"), std::string::npos);
}

}  // namespace
}  // namespace hrgbench::drivers::sim
