#pragma once
// The units a gyro's rate errors are read in (IEEE 952 / 1431): the code computes in rad/s and
// rad/√s, the verdict, the text output and the report show °/h and °/√h. One place for the factors.

#include <numbers>

namespace hrgbench::analysis {

inline constexpr double kDegPerRad = 180.0 / std::numbers::pi;
// °/h per rad/s (a rate, a bias, a bias instability).
inline constexpr double kDegPerHourPerRadPerS = kDegPerRad * 3600.0;
// °/√h per rad/√s (an angle random walk): √3600 = 60.
inline constexpr double kDegPerSqrtHourPerRadPerSqrtS = kDegPerRad * 60.0;

}  // namespace hrgbench::analysis
