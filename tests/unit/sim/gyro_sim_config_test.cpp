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

TEST(GyroSimConfigTest, ShippedCarrierExampleLoads) {
  const auto config =
      LoadGyroSimConfig(HRGBENCH_SOURCE_DIR "/drivers/sim/gyro_sim_carrier.example.toml");
  ASSERT_TRUE(config.has_value()) << config.error().ToString();
  const GyroSimOptions& o = config->options;
  EXPECT_EQ(o.physics, GyroPhysics::kCarrier);
  EXPECT_DOUBLE_EQ(o.carrier.resonator.decay_time_s, 1000.0);
  EXPECT_DOUBLE_EQ(o.carrier.resonator.frequency_split_hz, 0.01);
  EXPECT_DOUBLE_EQ(o.carrier.pickoff.errors.gain_ratio, 0.98);
  EXPECT_DOUBLE_EQ(o.carrier.pickoff.common_delay_s, 2e-6);
  EXPECT_EQ(o.carrier.electronics.reference.mode, ReferenceMode::kFreeRunning);
  EXPECT_EQ(o.carrier.electronics.filter_order, 4);
}

TEST(GyroSimConfigTest, PhysicsDefaultsToSlowAndCarrierKeysAreStrict) {
  const auto plain = ParseGyroSimConfig("[model]\nseed = 3\n", "sim.toml");
  ASSERT_TRUE(plain.has_value()) << plain.error().ToString();
  EXPECT_EQ(plain->options.physics, GyroPhysics::kSlow);

  const auto tracking = ParseGyroSimConfig(
      "[model]\nphysics = \"carrier\"\n[carrier]\nreference = \"tracking\"\n"
      "pll_bandwidth_hz = 5\n",
      "sim.toml");
  ASSERT_TRUE(tracking.has_value()) << tracking.error().ToString();
  EXPECT_EQ(tracking->options.carrier.electronics.reference.mode, ReferenceMode::kTracking);
  EXPECT_DOUBLE_EQ(tracking->options.carrier.electronics.reference.pll_bandwidth_hz, 5.0);

  struct Case {
    const char* text;
    const char* message;
  };
  const Case cases[] = {
      // [carrier] without the carrier physics, slow keys with it.
      {"[carrier]\nfrequency_hz = 5000\n", "[carrier] applies only to [model] physics"},
      {"[model]\nphysics = \"carrier\"\nsigma = 1e-4\n",
       "sim.toml:3: key 'model.sigma' = 1e-4: not allowed here: applies only to physics = "
       "\"slow\""},
      {"[model]\nphysics = \"fast\"\n", "sim.toml:2: key 'model.physics' = \"fast\""},
      // Bounds at the key, with the value as written.
      {"[model]\nphysics = \"carrier\"\n[carrier]\ndecay_time_s = -1\n",
       "sim.toml:4: key 'carrier.decay_time_s' = -1: out of range: must be in (0, 1e7] s"},
      {"[model]\nphysics = \"carrier\"\n[carrier]\nfilter_order = 5\n",
       "sim.toml:4: key 'carrier.filter_order' = 5: out of range: must be even"},
      {"[model]\nphysics = \"carrier\"\n[carrier]\nsample_rate_hz = 12000\n",
       "sim.toml:4: key 'carrier.sample_rate_hz' = 12000: out of range: must be >= 4 * "
       "frequency_hz"},
      {"[model]\nphysics = \"carrier\"\n[carrier]\nfilter_cutoff_hz = 2000\n",
       "sim.toml:4: key 'carrier.filter_cutoff_hz' = 2000: out of range: must be <= frequency_hz / "
       "4"},
      {"[model]\nphysics = \"carrier\"\n[carrier]\ngain_ratio = 3\n",
       "sim.toml:4: key 'carrier.gain_ratio' = 3: out of range"},
      // Keys of the other reference mode, and misspelt keys.
      {"[model]\nphysics = \"carrier\"\n[carrier]\npll_bandwidth_hz = 3\n",
       "key 'carrier.pll_bandwidth_hz' = 3: not allowed here: applies only to reference = "
       "\"tracking\""},
      {"[model]\nphysics = \"carrier\"\n[carrier]\nreference = \"tracking\"\n"
       "reference_offset_hz = 0.1\n",
       "key 'carrier.reference_offset_hz' = 0.1: not allowed here: applies only to reference = "
       "\"free-running\""},
      {"[model]\nphysics = \"carrier\"\n[carrier]\ndecay_time = 10\n",
       "sim.toml:4: key 'carrier.decay_time' = 10: unknown key (allowed here: frequency_hz"},
  };
  for (const Case& c : cases) {
    const auto config = ParseGyroSimConfig(c.text, "sim.toml");
    ASSERT_FALSE(config.has_value()) << c.text;
    EXPECT_NE(config.error().ToString().find(c.message), std::string::npos)
        << c.text << "\n -> " << config.error().ToString();
  }
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

TEST(GyroSimConfigTest, TheParameterBlockFaultsAreReadAndBounded) {
  const auto config = ParseGyroSimConfig(
      "[faults]\npower_loss_on_commit = 2\ncorrupt_parameter_word = 47\n", "sim.toml");
  ASSERT_TRUE(config.has_value()) << config.error().ToString();
  EXPECT_EQ(config->options.faults.power_loss_on_commit, 2u);
  EXPECT_EQ(config->options.faults.corrupt_parameter_word, 47);
  const auto beyond = ParseGyroSimConfig("[faults]\ncorrupt_parameter_word = 48\n", "sim.toml");
  ASSERT_FALSE(beyond.has_value());
  EXPECT_NE(beyond.error().ToString().find("sim.toml:2: key 'faults.corrupt_parameter_word' = 48"),
            std::string::npos)
      << beyond.error().ToString();
}

TEST(GyroSimConfigTest, ErrorsNameFileLineKeyAndValue) {
  const auto unknown = ParseGyroSimConfig("[model]\nsigma = 1e-4\nsigmaa = 2\n", "sim.toml");
  ASSERT_FALSE(unknown.has_value());
  EXPECT_EQ(unknown.error().ToString(),
            "sim.toml:3: key 'model.sigmaa' = 2: unknown key (allowed here: physics, delta, xi, "
            "sigma, seed)");
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
