// The station file's [site] table: the sensitive axis given as a vector (normalised by the loader)
// or as elevation and azimuth, never both; the Earth rate of what was loaded (site.hpp).

#include <gtest/gtest.h>

#include <string>

#include "hrgbench/config/site.hpp"
#include "hrgbench/config/station_config.hpp"

namespace hrgbench::bench {
namespace {

TEST(StationSiteKeys, LoaderNormalisesTheAxisAndAcceptsEitherForm) {
  auto station = ParseStationConfig(
      "[station]\nname = \"x\"\nkind = \"simulated\"\n[site]\nlatitude_deg = 45.0\n"
      "axis_enu = [0.0, 0.7071, 0.7071]\n[simulated]\n",
      "s.toml");
  ASSERT_TRUE(station.has_value()) << station.error().ToString();
  const auto& u = station->site.axis_enu;
  EXPECT_NEAR(u[0] * u[0] + u[1] * u[1] + u[2] * u[2], 1.0, 1e-15);
  // Axis at 45° elevation towards north, at 45° N: cos²45 + sin²45 = 1 → the full rate.
  EXPECT_NEAR(EarthRateOnAxisRadS(station->site), kEarthRateRadS, 1e-18);

  auto by_angles = ParseStationConfig(
      "[station]\nname = \"x\"\nkind = \"simulated\"\n[site]\nlatitude_deg = 45.0\n"
      "axis_elevation_deg = 45.0\naxis_azimuth_deg = 0.0\n[simulated]\n",
      "s.toml");
  ASSERT_TRUE(by_angles.has_value()) << by_angles.error().ToString();
  EXPECT_NEAR(EarthRateOnAxisRadS(by_angles->site), kEarthRateRadS, 1e-18);
}

TEST(StationSiteKeys, BothAxisFormsAtOnceIsAnError) {
  auto station = ParseStationConfig(
      "[station]\nname = \"x\"\nkind = \"simulated\"\n[site]\nlatitude_deg = 45.0\n"
      "axis_enu = [0.0, 0.0, 1.0]\naxis_elevation_deg = 90.0\naxis_azimuth_deg = 0.0\n"
      "[simulated]\n",
      "s.toml");
  ASSERT_FALSE(station.has_value());
  EXPECT_EQ(station.error().key, "site.axis_enu");
  EXPECT_EQ(station.error().line, 6u);
  EXPECT_NE(station.error().message.find("either"), std::string::npos);
}

}  // namespace
}  // namespace hrgbench::bench
