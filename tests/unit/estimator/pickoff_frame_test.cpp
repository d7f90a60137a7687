// The physical pick-off and the model's frame (pickoff_frame.hpp), checked against what does not
// share its algebra: the real 4×4 system and distortion matrices of MODEL.md (model.hpp) and
// Eigen's general matrix exponential, and the electrode geometry written out here.

#include "hrgbench/estimator/pickoff_frame.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <unsupported/Eigen/MatrixFunctions>

#include "hrgbench/estimator/model.hpp"
#include "hrgbench/estimator/physical_parameters.hpp"

namespace hrgbench::estimator {
namespace {

using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;

// A pick-off with every error at once, large enough that second-order terms are ~1e-5.
PickoffParameters EveryError() { return {1.03, 0.02, 0.004, 0.006}; }

// The real 4×4 form of a complex 2×2 acting on u = (x1 + i·x2, x3 + i·x4).
Matrix4 Real4(const Eigen::Matrix2cd& m) {
  Matrix4 out;
  for (int r = 0; r < 2; ++r) {
    for (int c = 0; c < 2; ++c) {
      const Complex z = m(r, c);
      out.block<2, 2>(2 * r, 2 * c) << z.real(), -z.imag(), z.imag(), z.real();
    }
  }
  return out;
}

TEST(PickoffFrameTest, PhysicalGainIsTheElectrodeGeometryGainsAndCrossTalk) {
  const PickoffParameters p = EveryError();
  const Complex rho = std::polar(p.gain_ratio, -p.phase_mismatch_rad);
  const Complex late = Complex(0.0, -p.cross_talk);  // κ·e^{−iπ/2}
  // Channel 2's electrode at 90° − ε reads q1·sin ε + q2·cos ε.
  const double s = std::sin(p.electrode_angle_error_rad), c = std::cos(p.electrode_angle_error_rad);
  const Eigen::Matrix2cd before = PhysicalPickoffGain(p, CrossTalkStage::kBeforeGain);
  EXPECT_NEAR(std::abs(before(0, 0) - (1.0 + late * s)), 0.0, 1e-15);
  EXPECT_NEAR(std::abs(before(0, 1) - late * c), 0.0, 1e-15);
  EXPECT_NEAR(std::abs(before(1, 0) - rho * (late + s)), 0.0, 1e-15);
  EXPECT_NEAR(std::abs(before(1, 1) - rho * c), 0.0, 1e-15);
  const Eigen::Matrix2cd after = PhysicalPickoffGain(p, CrossTalkStage::kAfterGain);
  EXPECT_NEAR(std::abs(after(0, 0) - (1.0 + late * rho * s)), 0.0, 1e-15);
  EXPECT_NEAR(std::abs(after(1, 0) - (late + rho * s)), 0.0, 1e-15);
}

// H = c·(I + C(ξ))·V(a) holds exactly for a general complex 2×2 (every entry different).
TEST(PickoffFrameTest, DecompositionReproducesAnyGain) {
  Eigen::Matrix2cd h;
  h << Complex(0.9, 0.1), Complex(0.02, -0.03), Complex(-0.05, 0.01), Complex(1.1, -0.04);
  const PickoffInModelFrame d = DecomposePickoffGain(h);
  const Complex ca = std::cos(d.frame_angle), sa = std::sin(d.frame_angle);
  Eigen::Matrix2cd v;
  v << ca, -sa, sa, ca;
  const Eigen::Matrix2cd back = d.common * ComplexDistortion(d.xi) * v;
  EXPECT_LT((back - h).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(PickoffFrameTest, RoundTripsAreExactForBothStages) {
  for (const CrossTalkStage stage : {CrossTalkStage::kBeforeGain, CrossTalkStage::kAfterGain}) {
    const PickoffParameters p = EveryError();
    const PhysicalPickoff back = PhysicalPickoffFromXi(XiFromPickoff(p, stage), stage);
    EXPECT_TRUE(back.converged);
    EXPECT_NEAR(back.pickoff.gain_ratio, p.gain_ratio, 1e-12);
    EXPECT_NEAR(back.pickoff.phase_mismatch_rad, p.phase_mismatch_rad, 1e-12);
    EXPECT_NEAR(back.pickoff.cross_talk, p.cross_talk, 1e-12);
    EXPECT_NEAR(back.pickoff.electrode_angle_error_rad, p.electrode_angle_error_rad, 1e-12);
    const Complex a = DecomposePickoffGain(PhysicalPickoffGain(p, stage)).frame_angle;
    EXPECT_NEAR(std::abs(back.frame_angle - a), 0.0, 1e-12);
  }
}

// To first order each ξ is the named error, and a misplaced electrode turns the model's frame by
// half its error: the model sits between the two electrodes.
TEST(PickoffFrameTest, ToFirstOrderEachXiIsTheNamedErrorAndTheFrameSitsBetweenTheElectrodes) {
  const Xi xi = XiFromPickoff({1.0 + 2e-4, 4e-4, 3e-4, 6e-4});
  EXPECT_NEAR(xi[kGainMismatch], -1e-4, 1e-7);
  EXPECT_NEAR(xi[kPhaseMismatch], -2e-4, 1e-7);
  EXPECT_NEAR(xi[kCrossTalk], 3e-4, 1e-7);
  EXPECT_NEAR(xi[kPickoffAngle], 3e-4, 1e-7);
  const PhysicalPickoff misplaced = PhysicalPickoffFromXi(XiFromPickoff({1.0, 0.0, 0.0, 0.01}));
  EXPECT_NEAR(misplaced.frame_angle.real(), 0.005, 1e-6);
  EXPECT_NEAR(misplaced.frame_angle.imag(), 0.0, 1e-15);
  // A gain error times a cross-talk, and a phase error times an electrode angle, give the frame
  // an imaginary part (the coupling that mixes the splits); the stages differ by K·G − G·K =
  // −κ·e^{−iπ/2}·(ρ − 1)·J, i.e. by about κ·|ρ − 1| in a.
  const PickoffParameters p = EveryError();
  const auto frame_angle = [&p](CrossTalkStage stage) {
    return DecomposePickoffGain(PhysicalPickoffGain(p, stage)).frame_angle;
  };
  const Complex before = frame_angle(CrossTalkStage::kBeforeGain);
  const Complex after = frame_angle(CrossTalkStage::kAfterGain);
  const Complex midway = frame_angle(CrossTalkStage::kMidway);
  EXPECT_GT(std::abs(before.imag()), 1e-5);
  const Complex rho = std::polar(p.gain_ratio, -p.phase_mismatch_rad);
  EXPECT_NEAR(std::abs(after - before), p.cross_talk * std::abs(rho - 1.0), 1e-5);
  // The nominal model sits halfway between the two ends.
  EXPECT_NEAR(std::abs(midway - 0.5 * (before + after)), 0.0, 1e-7);
  EXPECT_NEAR(std::abs(PhysicalPickoffFromXi(XiFromPickoff(p)).frame_angle - midway), 0.0, 1e-12);
}

// The data of a unit (electrode-frame anisotropies, physical pick-off) are the data of the model
// with its ξ and the anisotropies turned by 2a: y(t) = H·exp(A_q·t)·u0 equals
// c·(I + C(ξ))·exp(A_x·t)·x0 with x0 = V(a)·u0, evaluated with the real 4×4 matrices of MODEL.md.
TEST(PickoffFrameTest, AUnitsDataAreTheModelsWithTheTurnedAnisotropies) {
  ResonatorParameters r;
  r.decay_time_s = 300.0;
  r.damping_anisotropy_per_s = 2e-4;
  r.damping_axis_rad = 0.7;
  r.frequency_split_hz = 0.05;
  r.frequency_axis_rad = -0.3;
  r.angular_gain = 0.3;
  const Delta electrode_delta = DeltaFromResonator(r);
  for (const CrossTalkStage stage : {CrossTalkStage::kBeforeGain, CrossTalkStage::kAfterGain}) {
    const Eigen::Matrix2cd h = PhysicalPickoffGain(EveryError(), stage);
    const PickoffInModelFrame frame = DecomposePickoffGain(h);
    const Delta model_delta = DeltaInModelFrame(electrode_delta, frame.frame_angle);
    const Complex ca = std::cos(frame.frame_angle), sa = std::sin(frame.frame_angle);
    Eigen::Matrix2cd v;
    v << ca, -sa, sa, ca;
    const State u0(0.8, 0.1, -0.3, 0.4);
    const State x0 = Real4(v) * u0;
    for (double omega : {0.0, 1.0}) {
      for (double t : {0.0, 7.0, 40.0}) {
        const State unit = Real4(h) * (SystemMatrix(omega, electrode_delta) * t).exp() * u0;
        const State fitted = Real4(frame.common * Eigen::Matrix2cd::Identity()) *
                             (Matrix4::Identity() + DistortionMatrix(frame.xi)) *
                             (SystemMatrix(omega, model_delta) * t).exp() * x0;
        EXPECT_LT((unit - fitted).cwiseAbs().maxCoeff(), 1e-12) << "Ω " << omega << " t " << t;
      }
    }
    // And back.
    const Delta back = DeltaInElectrodeFrame(model_delta, frame.frame_angle);
    EXPECT_LT((back - electrode_delta).cwiseAbs().maxCoeff(), 1e-15);
  }
}

// The model's frame turns a misplaced electrode's axes by a: a wave held on the frequency axis
// measured from channel 1's electrode is, in the model, at that axis plus a.
TEST(PickoffFrameTest, TheModelsAxesAreChannelOnesTurnedByTheFrameAngle) {
  ResonatorParameters r;
  r.frequency_split_hz = 0.02;
  r.frequency_axis_rad = 0.4;
  const double epsilon = 0.0035;  // 0.1° on the shell
  const Complex a = PhysicalPickoffFromXi(XiFromPickoff({1.0, 0.0, 0.0, epsilon})).frame_angle;
  const ResonatorParameters seen =
      ResonatorFromDelta(DeltaInModelFrame(DeltaFromResonator(r), a), r.frequency_hz);
  EXPECT_NEAR(seen.frequency_axis_rad, 0.4 + epsilon / 2, 1e-9);
  EXPECT_NEAR(seen.frequency_split_hz, 0.02, 1e-15);
}

}  // namespace
}  // namespace hrgbench::estimator
