#include <cmath>
#include <numbers>

#include "hrgbench/config/site.hpp"

namespace hrgbench::bench {
namespace {
constexpr double kRadPerDeg = std::numbers::pi / 180.0;
}  // namespace

double EarthRateOnAxisRadS(double latitude_deg, const std::array<double, 3>& axis_enu) {
  // Earth's rotation vector in the local level frame (east, north, up): it lies in the meridian
  // plane, tilted up from the northern horizon by the latitude, so it has no east component.
  const double phi = latitude_deg * kRadPerDeg;
  return kEarthRateRadS * (axis_enu[1] * std::cos(phi) + axis_enu[2] * std::sin(phi));
}

double EarthRateOnAxisRadS(const SiteConfig& site) {
  return EarthRateOnAxisRadS(site.latitude_deg, site.axis_enu);
}

std::array<double, 3> AxisFromElevationAzimuth(double elevation_deg, double azimuth_deg) {
  const double el = elevation_deg * kRadPerDeg;
  const double az = azimuth_deg * kRadPerDeg;
  return {std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el)};
}

}  // namespace hrgbench::bench
