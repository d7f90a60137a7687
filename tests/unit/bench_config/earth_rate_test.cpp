// Earth-rate component on the sensitive axis, against values derived by hand:
// Ω_earth (ENU) = Ω_E·(0, cos φ, sin φ); component on the unit axis u is Ω_E·(u_n cos φ + u_u sin
// φ).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "hrgbench/bench/station_config.hpp"

namespace hrgbench::bench {
namespace {

constexpr double kTol = 1e-19;  // rad/s; Ω_E ≈ 7.3e-5, so 1e-19 is rounding

StationConfig At(double latitude_deg, std::array<double, 3> axis_enu) {
  StationConfig station;
  station.site.latitude_deg = latitude_deg;
  station.site.axis_enu = axis_enu;
  return station;
}

TEST(EarthRate, AxisUpAt45DegreesIsSinOf45) {
  EXPECT_NEAR(EarthRateOnAxisRadS(At(45.0, {0, 0, 1})), kEarthRateRadS * std::sqrt(0.5), kTol);
}

TEST(EarthRate, AxisNorthAtTheEquatorIsTheFullRate) {
  EXPECT_NEAR(EarthRateOnAxisRadS(At(0.0, {0, 1, 0})), 7.2921150e-5, kTol);
}

TEST(EarthRate, AxisUpAtThePolesIsPlusMinusTheFullRate) {
  EXPECT_NEAR(EarthRateOnAxisRadS(At(90.0, {0, 0, 1})), kEarthRateRadS, kTol);
  EXPECT_NEAR(EarthRateOnAxisRadS(At(-90.0, {0, 0, 1})), -kEarthRateRadS, kTol);
}

TEST(EarthRate, AxisUpAtTheEquatorAndAxisEastAnywhereSeeNothing) {
  EXPECT_NEAR(EarthRateOnAxisRadS(At(0.0, {0, 0, 1})), 0.0, kTol);
  EXPECT_NEAR(EarthRateOnAxisRadS(At(55.7558, {1, 0, 0})), 0.0, kTol);
}

TEST(EarthRate, AxisAlongTheEarthsAxisSeesTheFullRate) {
  // At latitude φ, the axis pointing north elevated by φ is parallel to the Earth's axis.
  const double phi = 30.0;
  const auto axis = AxisFromElevationAzimuth(phi, 0.0);
  EXPECT_NEAR(EarthRateOnAxisRadS(At(phi, axis)), kEarthRateRadS, kTol);
}

TEST(EarthRate, ElevationAzimuthConvention) {
  const auto up = AxisFromElevationAzimuth(90.0, 123.0);
  EXPECT_NEAR(up[2], 1.0, 1e-15);
  const auto east = AxisFromElevationAzimuth(0.0, 90.0);  // azimuth clockwise from north
  EXPECT_NEAR(east[0], 1.0, 1e-15);
  EXPECT_NEAR(east[1], 0.0, 1e-15);
  // Axis 60° above the northern horizon at 45° N: Ω_E (cos 60° cos 45° + sin 60° sin 45°).
  const double expected = kEarthRateRadS * std::cos(15.0 * std::numbers::pi / 180.0);
  EXPECT_NEAR(EarthRateOnAxisRadS(At(45.0, AxisFromElevationAzimuth(60.0, 0.0))), expected, kTol);
}

TEST(EarthRate, LoaderNormalisesTheAxisAndAcceptsEitherForm) {
  auto station = ParseStationConfig(
      "[station]\nname = \"x\"\nkind = \"simulated\"\n[site]\nlatitude_deg = 45.0\n"
      "axis_enu = [0.0, 0.7071, 0.7071]\n[simulated]\n",
      "s.toml");
  ASSERT_TRUE(station.has_value()) << station.error().ToString();
  const auto& u = station->site.axis_enu;
  EXPECT_NEAR(u[0] * u[0] + u[1] * u[1] + u[2] * u[2], 1.0, 1e-15);
  // Axis at 45° elevation towards north, at 45° N: cos²45 + sin²45 = 1 → the full rate.
  EXPECT_NEAR(EarthRateOnAxisRadS(*station), kEarthRateRadS, 1e-18);

  auto by_angles = ParseStationConfig(
      "[station]\nname = \"x\"\nkind = \"simulated\"\n[site]\nlatitude_deg = 45.0\n"
      "axis_elevation_deg = 45.0\naxis_azimuth_deg = 0.0\n[simulated]\n",
      "s.toml");
  ASSERT_TRUE(by_angles.has_value()) << by_angles.error().ToString();
  EXPECT_NEAR(EarthRateOnAxisRadS(*by_angles), kEarthRateRadS, 1e-18);
}

TEST(EarthRate, BothAxisFormsAtOnceIsAnError) {
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
