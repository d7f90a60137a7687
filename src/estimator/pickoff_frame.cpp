#include "hrgbench/estimator/pickoff_frame.hpp"

#include <Eigen/Dense>
#include <cmath>

#include "hrgbench/estimator/frequency_drift_decay.hpp"
#include "hrgbench/estimator/split_coriolis_mixing.hpp"

namespace hrgbench::estimator {
namespace {

using Complex = std::complex<double>;
constexpr Complex kI(0.0, 1.0);

// The anisotropy pair (D_c, D_s) = (δ3 + iδ5, δ4 + iδ6) turned by the complex angle φ.
Delta Turned(const Delta& delta, Complex phi) noexcept {
  const Complex dc(delta[kDampingAnisotropyCos], delta[kFrequencyAnisotropyCos]);
  const Complex ds(delta[kDampingAnisotropySin], delta[kFrequencyAnisotropySin]);
  const Complex c = std::cos(phi), s = std::sin(phi);
  const Complex tc = c * dc - s * ds, ts = s * dc + c * ds;
  Delta out = delta;
  out[kDampingAnisotropyCos] = tc.real();
  out[kFrequencyAnisotropyCos] = tc.imag();
  out[kDampingAnisotropySin] = ts.real();
  out[kFrequencyAnisotropySin] = ts.imag();
  return out;
}

PickoffParameters Unpacked(const Eigen::Vector4d& v) {
  PickoffParameters p;
  p.gain_ratio = v[0];
  p.phase_mismatch_rad = v[1];
  p.cross_talk = v[2];
  p.electrode_angle_error_rad = v[3];
  return p;
}

}  // namespace

const char* ToString(CrossTalkStage stage) noexcept {
  switch (stage) {
    case CrossTalkStage::kMidway:
      return "midway";
    case CrossTalkStage::kBeforeGain:
      return "before_gain";
    case CrossTalkStage::kAfterGain:
      return "after_gain";
  }
  return "?";
}

Eigen::Matrix2cd PhysicalPickoffGain(const PickoffParameters& p, CrossTalkStage stage) noexcept {
  Eigen::Matrix2cd gains = Eigen::Matrix2cd::Identity();
  gains(1, 1) = std::polar(p.gain_ratio, -p.phase_mismatch_rad);
  const auto coupling = [](double kappa) {
    Eigen::Matrix2cd k = Eigen::Matrix2cd::Identity();
    k(0, 1) = k(1, 0) = -kI * kappa;
    return k;
  };
  Eigen::Matrix2cd electrodes;
  electrodes << 1.0, 0.0, std::sin(p.electrode_angle_error_rad),
      std::cos(p.electrode_angle_error_rad);
  switch (stage) {
    case CrossTalkStage::kBeforeGain:
      return gains * coupling(p.cross_talk) * electrodes;
    case CrossTalkStage::kAfterGain:
      return coupling(p.cross_talk) * gains * electrodes;
    case CrossTalkStage::kMidway:
      break;
  }
  const Eigen::Matrix2cd half = coupling(0.5 * p.cross_talk);
  return half * gains * half * electrodes;
}

PickoffInModelFrame DecomposePickoffGain(const Eigen::Matrix2cd& h) noexcept {
  PickoffInModelFrame out;
  // H·V(a)⁻¹ must be symmetric: its (1,2) and (2,1) entries are cos a·H12 + sin a·H11 and
  // cos a·H21 − sin a·H22.
  out.frame_angle = std::atan((h(1, 0) - h(0, 1)) / (h(0, 0) + h(1, 1)));
  const Complex c = std::cos(out.frame_angle), s = std::sin(out.frame_angle);
  Eigen::Matrix2cd v_inverse;  // V(−a) = cos a·I − sin a·J
  v_inverse << c, s, -s, c;
  const Eigen::Matrix2cd m = h * v_inverse;
  out.common = 0.5 * (m(0, 0) + m(1, 1));
  const Complex p = 0.5 * (m(0, 0) - m(1, 1)) / out.common;
  const Complex q = 0.5 * (m(0, 1) + m(1, 0)) / out.common;
  out.xi[kGainMismatch] = p.real();
  out.xi[kPhaseMismatch] = -p.imag();
  out.xi[kPickoffAngle] = q.real();
  out.xi[kCrossTalk] = -q.imag();
  return out;
}

PhysicalPickoff PhysicalPickoffFromXi(const Xi& xi, CrossTalkStage stage) noexcept {
  const auto xi_of = [stage](const Eigen::Vector4d& v) {
    return DecomposePickoffGain(PhysicalPickoffGain(Unpacked(v), stage)).xi;
  };
  // First order: ξ1 = (1 − g)/2, ξ2 = −Δφ/2, ξ3 = κ, ξ4 = ε/2.
  Eigen::Vector4d v(1.0 - 2.0 * xi[kGainMismatch], -2.0 * xi[kPhaseMismatch], xi[kCrossTalk],
                    2.0 * xi[kPickoffAngle]);
  PhysicalPickoff out;
  for (int iteration = 0; iteration < 20; ++iteration) {
    const Xi residual = xi_of(v) - xi;
    if (!residual.allFinite()) break;
    if (residual.cwiseAbs().maxCoeff() <= 1e-13) {
      out.converged = true;
      break;
    }
    // The map is within O(|ξ|) of a constant linear one, so a finite-difference Jacobian at a
    // fixed small step is accurate enough for quadratic convergence.
    Eigen::Matrix4d jacobian;
    for (int j = 0; j < 4; ++j) {
      constexpr double kStep = 1e-6;
      Eigen::Vector4d plus = v, minus = v;
      plus[j] += kStep;
      minus[j] -= kStep;
      jacobian.col(j) = (xi_of(plus) - xi_of(minus)) / (2.0 * kStep);
    }
    v -= jacobian.partialPivLu().solve(residual);
  }
  out.pickoff = Unpacked(v);
  out.frame_angle = DecomposePickoffGain(PhysicalPickoffGain(out.pickoff, stage)).frame_angle;
  return out;
}

Xi XiFromPickoff(const PickoffParameters& pickoff, CrossTalkStage stage) noexcept {
  return DecomposePickoffGain(PhysicalPickoffGain(pickoff, stage)).xi;
}

PickoffParameters PickoffFromXi(const Xi& xi, CrossTalkStage stage) noexcept {
  return PhysicalPickoffFromXi(xi, stage).pickoff;
}

Delta DeltaInElectrodeFrame(const Delta& model_delta, std::complex<double> frame_angle) noexcept {
  return Turned(model_delta, -2.0 * frame_angle);
}

Delta DeltaInModelFrame(const Delta& electrode_delta, std::complex<double> frame_angle) noexcept {
  return Turned(electrode_delta, 2.0 * frame_angle);
}

SlowModelTruth SlowModelSeenOnUnit(const ResonatorParameters& resonator,
                                   const Eigen::Matrix2cd& pickoff_gain,
                                   double relative_frequency_rate_per_s) noexcept {
  const PickoffInModelFrame frame = DecomposePickoffGain(pickoff_gain);
  SlowModelTruth out;
  out.frame_angle = frame.frame_angle;
  out.delta = DeltaInModelFrame(DeltaFromResonator(resonator), frame.frame_angle);
  out.delta[kDamping] =
      DecayRateSeenUnderFrequencyDrift(out.delta[kDamping], relative_frequency_rate_per_s);
  out.xi = XiSeenBySlowModel(frame.xi, out.delta, resonator.frequency_hz);
  return out;
}

}  // namespace hrgbench::estimator
