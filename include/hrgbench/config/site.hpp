#pragma once
// The station's site: where it stands (latitude) and how the gyro's sensitive axis points, and
// what that makes of the Earth's rotation — the Earth-rate component on the sensitive axis, which
// the bench adds to the measured table rate to give the estimator Ω. The gyro's sensitive axis is
// the table's rotation axis (that is what makes the table rate Ω), fixed in the local level frame,
// so the Earth-rate component on it is a constant per station.
//
// Pure functions and plain data; thread-safe; no allocation (usable anywhere). The station file's
// [site] table (station_config.hpp, bench_configs/README.md) is read into a SiteConfig.

#include <array>

namespace hrgbench::bench {

// Earth's sidereal rotation rate (WGS-84 / IERS value), rad/s.
inline constexpr double kEarthRateRadS = 7.2921150e-5;

struct SiteConfig {
  double latitude_deg = 0.0;  // geodetic latitude φ, [-90, 90], north positive
  // Unit vector of the sensitive axis in the local level frame (east, north, up); normalised by
  // the loader. Default: the axis points up (a table with a vertical axis).
  std::array<double, 3> axis_enu = {0.0, 0.0, 1.0};
};

// Ω_earth on the sensitive axis, rad/s: the Earth-rate vector in the local level frame (east,
// north, up) is Ω_E·(0, cos φ, sin φ), so its component on the unit axis u is
// Ω_E·(u_n·cos φ + u_u·sin φ). Axis up at 45° N: Ω_E·sin 45°; axis north at the equator: Ω_E.
double EarthRateOnAxisRadS(const SiteConfig& site);
double EarthRateOnAxisRadS(double latitude_deg, const std::array<double, 3>& axis_enu);

// Unit vector in (east, north, up) from elevation above the horizon and azimuth clockwise from
// north (navigation convention): (cos el·sin az, cos el·cos az, sin el).
std::array<double, 3> AxisFromElevationAzimuth(double elevation_deg, double azimuth_deg);

}  // namespace hrgbench::bench
