// The map between the physical parameters of the mode and the pick-off path and the model's
// (δ, ξ) (estimator/physical_parameters.hpp): exact round trips both ways, and the meaning of each
// number checked on the model itself (the eigenvalues of A's complex form along the named axes).
// The brute-force check against the carrier-level oscillator is
// tests/unit/sim/carrier_resonator_test.

#include "hrgbench/estimator/physical_parameters.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <numbers>

#include "hrgbench/estimator/model.hpp"
#include "hrgbench/estimator/simulation.hpp"

namespace hrgbench::estimator {
namespace {

constexpr double kPi = std::numbers::pi;

ResonatorParameters SomeResonator() {
  ResonatorParameters r;
  r.frequency_hz = 5123.0;
  r.decay_time_s = 812.0;
  r.damping_anisotropy_per_s = 3.1e-4;
  r.damping_axis_rad = -0.7;
  r.frequency_split_hz = 0.0421;
  r.frequency_axis_rad = 1.2;
  r.angular_gain = 0.283;
  return r;
}

// The complex form of A acting on u: A·x for x = (1, 0, 0, 0) etc. read back as complex columns.
Eigen::Matrix2cd ComplexSystem(double omega, const Delta& delta) {
  const Matrix4 a = SystemMatrix(omega, delta);
  Eigen::Matrix2cd m;
  for (int col = 0; col < 2; ++col) {
    // Column for u_col = 1: x with x_{2col} = 1.
    const State x = State::Unit(2 * col);
    const State ax = a * x;
    m(0, col) = {ax[0], ax[1]};
    m(1, col) = {ax[2], ax[3]};
  }
  return m;
}

TEST(PhysicalParametersTest, ResonatorRoundTripIsExact) {
  const ResonatorParameters r = SomeResonator();
  const ResonatorParameters back = ResonatorFromDelta(DeltaFromResonator(r), r.frequency_hz);
  EXPECT_NEAR(back.decay_time_s, r.decay_time_s, 1e-12 * r.decay_time_s);
  EXPECT_NEAR(back.damping_anisotropy_per_s, r.damping_anisotropy_per_s, 1e-12 * 3.1e-4);
  EXPECT_NEAR(back.damping_axis_rad, r.damping_axis_rad, 1e-12);
  EXPECT_NEAR(back.frequency_split_hz, r.frequency_split_hz, 1e-12 * 0.0421);
  EXPECT_NEAR(back.frequency_axis_rad, r.frequency_axis_rad, 1e-12);
  EXPECT_EQ(back.angular_gain, r.angular_gain);
  EXPECT_EQ(back.frequency_hz, r.frequency_hz);
}

TEST(PhysicalParametersTest, DeltaRoundTripIsExactForAnyDelta) {
  NormalGenerator normal(7);
  for (int trial = 0; trial < 200; ++trial) {
    Delta delta;
    delta << -std::abs(normal.Next()) * 1e-3 - 1e-6, 0.3 + 0.01 * normal.Next(),
        1e-4 * normal.Next(), 1e-4 * normal.Next(), 0.1 * normal.Next(), 0.1 * normal.Next();
    const Delta back = DeltaFromResonator(ResonatorFromDelta(delta, 5000.0));
    for (int i = 0; i < 6; ++i) {
      EXPECT_NEAR(back[i], delta[i], 1e-12 * std::max(std::abs(delta[i]), 1e-4)) << i;
    }
  }
}

TEST(PhysicalParametersTest, AxesComeBackInTheirCanonicalRange) {
  ResonatorParameters r = SomeResonator();
  r.frequency_axis_rad = 1.2 + kPi;  // the same axis
  r.damping_axis_rad = -0.7 - kPi;
  const ResonatorParameters back = ResonatorFromDelta(DeltaFromResonator(r), r.frequency_hz);
  EXPECT_NEAR(back.frequency_axis_rad, 1.2, 1e-12);
  EXPECT_NEAR(back.damping_axis_rad, -0.7, 1e-12);
  r.frequency_split_hz = 0.0;  // no split: no axis
  EXPECT_EQ(ResonatorFromDelta(DeltaFromResonator(r), r.frequency_hz).frequency_axis_rad, 0.0);
}

// The pick-off's physical errors and their maps: pickoff_frame_test.cpp.

TEST(PhysicalParametersTest, ComplexDistortionIsTheModelsC) {
  const Xi xi(0.01, -0.003, 0.002, 0.004);
  const Eigen::Matrix2cd h = ComplexDistortion(xi);
  const Matrix4 ic = Matrix4::Identity() + DistortionMatrix(xi);
  const State x(0.3, -0.2, 0.7, 0.1);
  const State y = ic * x;
  const Eigen::Vector2cd w =
      h * Eigen::Vector2cd(std::complex<double>(x[0], x[1]), std::complex<double>(x[2], x[3]));
  EXPECT_NEAR(std::abs(w[0] - std::complex<double>(y[0], y[1])), 0.0, 1e-15);
  EXPECT_NEAR(std::abs(w[1] - std::complex<double>(y[2], y[3])), 0.0, 1e-15);
}

// The meaning of each number on the model: the eigenvalues of A along the named axes.
TEST(PhysicalParametersTest, EachNumberMeansWhatItSaysOnTheModel) {
  ResonatorParameters r;
  r.decay_time_s = 500.0;
  r.angular_gain = 0.0;
  r.frequency_split_hz = 0.05;
  r.frequency_axis_rad = 0.4;
  const Eigen::Matrix2cd split = ComplexSystem(0.0, DeltaFromResonator(r));
  // A wave along θ_ω: u ∝ (cos θ_ω, sin θ_ω) is an eigenvector with eigenvalue −1/τ + iπΔf (it
  // vibrates at f0 + Δf/2), the orthogonal one at −1/τ − iπΔf.
  const Eigen::Vector2cd along(std::cos(0.4), std::sin(0.4));
  const Eigen::Vector2cd across(-std::sin(0.4), std::cos(0.4));
  const std::complex<double> up(-1.0 / 500.0, kPi * 0.05), down(-1.0 / 500.0, -kPi * 0.05);
  EXPECT_NEAR((split * along - up * along).norm(), 0.0, 1e-15);
  EXPECT_NEAR((split * across - down * across).norm(), 0.0, 1e-15);

  r.frequency_split_hz = 0.0;
  r.damping_anisotropy_per_s = 2e-4;
  r.damping_axis_rad = -0.3;
  const Eigen::Matrix2cd damping = ComplexSystem(0.0, DeltaFromResonator(r));
  const Eigen::Vector2cd d_along(std::cos(-0.3), std::sin(-0.3));
  EXPECT_NEAR((damping * d_along - (-1.0 / 500.0 - 1e-4) * d_along).norm(), 0.0, 1e-15);

  // Rotation: a standing wave's angle turns at −2kΩ (the shell's pattern at −kΩ).
  r.damping_anisotropy_per_s = 0.0;
  r.decay_time_s = 1e12;
  r.angular_gain = 0.3;
  const Delta delta = DeltaFromResonator(r);
  const double omega = 0.5, t = 1.3;
  const State x = PropagateExact(omega, delta, OrbitToState({1.0, 0.0, 0.2, 0.0}), t);
  const Orbit o = StateToOrbit(x);
  EXPECT_NEAR(o.theta_rad, 0.2 - 2.0 * 0.3 * omega * t, 1e-9);
}

TEST(PhysicalParametersTest, OscillatorCoefficientsAreTheStatedMatrices) {
  const ResonatorParameters r = SomeResonator();
  const OscillatorCoefficients o = OscillatorFromResonator(r, 1.001);
  // K's eigenvectors are the frequency axes, its eigenvalues (2π·f1,2·scale)².
  const Eigen::Vector2d along(std::cos(1.2), std::sin(1.2));
  const double w1 = 2 * kPi * (r.frequency_hz + 0.5 * r.frequency_split_hz) * 1.001;
  EXPECT_NEAR((o.stiffness * along - w1 * w1 * along).norm() / (w1 * w1), 0.0, 1e-15);
  const Eigen::Vector2d d_along(std::cos(-0.7), std::sin(-0.7));
  EXPECT_NEAR((o.damping * d_along - (2.0 / 812.0 + 3.1e-4) * d_along).norm(), 0.0, 1e-17);
  EXPECT_DOUBLE_EQ(o.coriolis, 4 * 0.283);
  EXPECT_NEAR(r.QualityFactor(), kPi * 5123.0 * 812.0, 1e-6);
}

TEST(PhysicalParametersTest, ValidationNamesTheField) {
  std::string why;
  ResonatorParameters r;
  EXPECT_TRUE(r.IsValid(&why)) << why;
  r.frequency_split_hz = -1.0;
  EXPECT_FALSE(r.IsValid(&why));
  EXPECT_NE(why.find("frequency_split_hz"), std::string::npos);
  PickoffParameters p;
  EXPECT_TRUE(p.IsValid(&why)) << why;
  p.gain_ratio = 0.0;
  EXPECT_FALSE(p.IsValid(&why));
  EXPECT_NE(why.find("gain_ratio"), std::string::npos);
}

}  // namespace
}  // namespace hrgbench::estimator
