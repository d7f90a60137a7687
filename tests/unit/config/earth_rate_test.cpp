// Earth-rate component on the sensitive axis, against values derived by hand:
// Ω_earth (ENU) = Ω_E·(0, cos φ, sin φ); component on the unit axis u is Ω_E·(u_n cos φ + u_u sin
// φ).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "hrgbench/config/site.hpp"

namespace hrgbench::bench {
namespace {

constexpr double kTol = 1e-19;  // rad/s; Ω_E ≈ 7.3e-5, so 1e-19 is rounding

SiteConfig At(double latitude_deg, std::array<double, 3> axis_enu) {
  SiteConfig site;
  site.latitude_deg = latitude_deg;
  site.axis_enu = axis_enu;
  return site;
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

}  // namespace
}  // namespace hrgbench::bench
