#pragma once
// Parameter vectors of the HRG free-run model (docs/estimator/model.md "Parameters").
//
// delta (δ, 6): mechanical parameters of the resonator.
//   δ1 damping [1/s, negative], δ2 angular gain (the Bryan factor; MODEL.md's "gyro scale
//   factor"; dimensionless, ≈ 0.3),
//   δ3, δ4 damping anisotropy [1/s], δ5, δ6 frequency anisotropy [rad/s].
// xi (ξ, 4): errors of the pick-off path, dimensionless and small (|ξ| ≪ 1).
//   ξ1 gain mismatch, ξ2 phase-delay mismatch, ξ3 cross-talk, ξ4 pick-off angle error.

#include <Eigen/Core>
#include <array>
#include <limits>
#include <string_view>

namespace hrgbench::estimator {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using Delta = Eigen::Matrix<double, 6, 1>;
using Xi = Eigen::Matrix<double, 4, 1>;
using State = Eigen::Matrix<double, 4, 1>;        // x = (x1, x2, x3, x4), slow variables
using Observation = Eigen::Matrix<double, 4, 1>;  // y = (y1, y2, y3, y4), demodulated channels
using Forms = Eigen::Matrix<double, 4, 1>;        // z = (Ac, As, K, S), principal quadratic forms

// Named indices into Delta (0-based; δ1 is kDamping).
inline constexpr int kDamping = 0;
inline constexpr int kScaleFactor = 1;
inline constexpr int kDampingAnisotropyCos = 2;
inline constexpr int kDampingAnisotropySin = 3;
inline constexpr int kFrequencyAnisotropyCos = 4;
inline constexpr int kFrequencyAnisotropySin = 5;

// Named indices into Xi.
inline constexpr int kGainMismatch = 0;
inline constexpr int kPhaseMismatch = 1;
inline constexpr int kCrossTalk = 2;
inline constexpr int kPickoffAngle = 3;

// Named indices into Forms.
inline constexpr int kAc = 0;
inline constexpr int kAs = 1;
inline constexpr int kK = 2;
inline constexpr int kS = 3;

inline constexpr std::array<std::string_view, 6> kDeltaNames = {"delta1", "delta2", "delta3",
                                                                "delta4", "delta5", "delta6"};
inline constexpr std::array<std::string_view, 6> kDeltaMeanings = {
    "damping [1/s]",
    "angular gain (Bryan factor) [-]",
    "damping anisotropy cos [1/s]",
    "damping anisotropy sin [1/s]",
    "frequency anisotropy cos [rad/s]",
    "frequency anisotropy sin [rad/s]"};
inline constexpr std::array<std::string_view, 4> kXiNames = {"xi1", "xi2", "xi3", "xi4"};
inline constexpr std::array<std::string_view, 4> kXiMeanings = {
    "gain mismatch [-]", "phase-delay mismatch [-]", "cross-talk [-]", "pick-off angle error [-]"};

// Which ξ components an estimator treats as unknown; the others are held at their given values.
using XiMask = std::array<bool, 4>;
inline constexpr XiMask kNoXi = {false, false, false, false};
inline constexpr XiMask kXi1Only = {true, false, false, false};
inline constexpr XiMask kAllXi = {true, true, true, true};

inline int CountEstimated(const XiMask& mask) {
  int n = 0;
  for (bool b : mask) n += b ? 1 : 0;
  return n;
}

}  // namespace hrgbench::estimator
