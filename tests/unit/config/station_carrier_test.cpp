// The simulated station's physics = "carrier" and its [simulated.carrier] table: the shipped
// carrier station reads as written, and the table is as strict as hrg-gyro-sim's [carrier]
// (drivers/sim/carrier_config.cpp): bounds at the key, cross-checks, keys of the other mode.

#include <gtest/gtest.h>

#include <string>

#include "hrgbench/config/station_config.hpp"

namespace hrgbench::bench {
namespace {

const std::string kHead =
    "[station]\nname = \"s\"\nkind = \"simulated\"\n[site]\nlatitude_deg = 0\n[simulated]\n";

TEST(StationCarrier, ShippedCarrierStationReadsAsWritten) {
  const auto station = LoadStationConfig(std::string(HRGBENCH_SOURCE_DIR) +
                                         "/bench_configs/station-sim-carrier.toml");
  ASSERT_TRUE(station.has_value()) << station.error().ToString();
  const SimulatedStationConfig& sim = station->simulated;
  EXPECT_EQ(sim.physics, SimulatedPhysics::kCarrier);
  EXPECT_DOUBLE_EQ(sim.carrier.resonator.decay_time_s, 1000.0);
  EXPECT_DOUBLE_EQ(sim.carrier.resonator.angular_gain, 0.3);
  EXPECT_DOUBLE_EQ(sim.carrier.pickoff.gain_ratio, 0.98);
  EXPECT_DOUBLE_EQ(sim.carrier.white_noise_std, 1.1e-3);
  EXPECT_FALSE(sim.carrier.tracking_reference);
  EXPECT_EQ(sim.carrier.filter_order, 4);
}

TEST(StationCarrier, DefaultPhysicsIsSlow) {
  const auto station = ParseStationConfig(kHead + "sigma = 0\n", "s.toml");
  ASSERT_TRUE(station.has_value()) << station.error().ToString();
  EXPECT_EQ(station->simulated.physics, SimulatedPhysics::kSlow);
}

TEST(StationCarrier, ErrorsNameTheKeyAndValue) {
  struct Case {
    std::string text;
    std::string message;
  };
  const Case cases[] = {
      {"physics = \"carrier\"\nsigma = 1e-4\n",
       "s.toml:8: key 'simulated.sigma' = 1e-4: not allowed here: applies only to physics = "
       "\"slow\""},
      {"physics = \"carrier\"\nresonant_frequency_hz = 5000\n",
       "key 'simulated.resonant_frequency_hz' = 5000: not allowed here"},
      {"[simulated.carrier]\nfrequency_hz = 5000\n",
       "[simulated.carrier] applies only to physics = \"carrier\""},
      {"physics = \"carrier\"\n[simulated.carrier]\ndecay_time_s = 0\n",
       "s.toml:9: key 'simulated.carrier.decay_time_s' = 0: out of range: must be in (0, 1e7] s"},
      {"physics = \"carrier\"\n[simulated.carrier]\nfilter_order = 3\n",
       "key 'simulated.carrier.filter_order' = 3: out of range: must be even"},
      {"physics = \"carrier\"\n[simulated.carrier]\nsample_rate_hz = 12000\n",
       "key 'simulated.carrier.sample_rate_hz' = 12000: out of range: must be >= 4 * "
       "frequency_hz"},
      {"physics = \"carrier\"\n[simulated.carrier]\nreference = \"tracking\"\n"
       "reference_offset_hz = 1\n",
       "key 'simulated.carrier.reference_offset_hz' = 1: not allowed here"},
      {"physics = \"carrier\"\n[simulated.carrier]\ncross_talk = 0.3\n",
       "key 'simulated.carrier.cross_talk' = 0.3: out of range"},
      {"physics = \"carrier\"\n[simulated.carrier]\nsplit_hz = 1\n",
       "key 'simulated.carrier.split_hz' = 1: unknown key"},
  };
  for (const Case& c : cases) {
    const auto station = ParseStationConfig(kHead + c.text, "s.toml");
    ASSERT_FALSE(station.has_value()) << c.text;
    EXPECT_NE(station.error().ToString().find(c.message), std::string::npos)
        << c.text << "\n -> " << station.error().ToString();
  }
}

}  // namespace
}  // namespace hrgbench::bench
