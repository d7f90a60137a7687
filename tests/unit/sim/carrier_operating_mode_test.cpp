// The gyro as a gyro at carrier level (issue 28 §1): the 2-DOF resonator at its 5 kHz carrier,
// driven through forcers by the electronics' command modulated onto their own reference, read by
// the pick-off channels and the demodulating electronics (CarrierSimulation's operating mode), run
// by the whole-angle loops and readout (WholeAngleControl) at a constant table rate. What it shows
// is compared with the slow model's laws (docs/estimator/operating-mode.md), written out here from
// the resonator's physical parameters (estimator/physical_parameters.hpp's map, by hand):
//
//   δ1 = −1/τ, δ2 = k, δ3 = −(Δ(1/τ)/2)·cos2θ_τ, δ4 = −(Δ(1/τ)/2)·sin2θ_τ,
//   δ5 = π·Δf·cos2θ_ω, δ6 = π·Δf·sin2θ_ω
//
//   the damping anisotropy's drift   Ω̂ − Ω = −(δ4·cos2θ − δ3·sin2θ)/(2δ2)
//   the forcers' gain and angle      (c, s) = (−g·β4, g·β1)/(2δ2), g = −δ1 the energy loop's effort
//
// and one the carrier adds: the demodulator's low-pass shows the wave τg late (its DC group delay;
// for an n-th order Butterworth at ωc, τg = Σ_k sin((2k − 1)π/(2n))/ωc over the n poles: 2.613/ωc
// at n = 4), so the energy loop's force g·x̂ lies along the wave as it was τg ago, a component
// −g·θ'·τg·J·x across it: θ' becomes θ'·(1 − g·τg), a scale factor −g·τg (2.08 ppm at τ = 1000 s,
// 200 Hz), which the readout removes when told the delay (WholeAngleLoopGains).
//
// Tolerances: the slow model's laws hold to first order in the small parameters and to the
// averaging's O(|A|/ω0) ≈ 1e-5; the forcers' zero-order hold and the filter change the loops'
// gains, not these laws.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "hrgbench/analysis/rate_error_harmonics.hpp"
#include "hrgbench/estimator/compensation.hpp"
#include "hrgbench/estimator/whole_angle_control.hpp"
#include "sim/carrier_simulation.hpp"

namespace hrgbench::drivers::sim {
namespace {

using estimator::CompensationSet;
constexpr double kH = 1e-3;  // the electronics' sample period, s
constexpr double kPi = std::numbers::pi;

std::string Figure(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

// An ideal pick-off and electronics: the resonator's own laws, nothing of the chain's errors.
CarrierOptions IdealChain() {
  CarrierOptions o;
  o.resonator.frequency_hz = 5000.0;
  o.resonator.decay_time_s = 1000.0;
  o.resonator.angular_gain = 0.3;
  o.sample_rate_hz = 100000.0;
  o.electronics.filter_order = 4;
  o.electronics.filter_cutoff_hz = 200.0;
  o.electronics.quantise = false;
  return o;
}

// δ from the resonator, by hand (above).
estimator::Delta HandDelta(const estimator::ResonatorParameters& r) {
  estimator::Delta d;
  d << -1.0 / r.decay_time_s, r.angular_gain,
      -0.5 * r.damping_anisotropy_per_s * std::cos(2.0 * r.damping_axis_rad),
      -0.5 * r.damping_anisotropy_per_s * std::sin(2.0 * r.damping_axis_rad),
      kPi * r.frequency_split_hz * std::cos(2.0 * r.frequency_axis_rad),
      kPi * r.frequency_split_hz * std::sin(2.0 * r.frequency_axis_rad);
  return d;
}

struct Trace {
  std::vector<double> angle_rad;
  std::vector<double> rate_error_rad_s;
  double max_quadrature_ratio = 0.0;
  double max_energy_error = 0.0;
  double mean_effort_per_s = 0.0;  // the amplitude loop's g over the kept samples
};

// `delay_known`: the readout is told the demodulator's group delay, as the electronics know it.
Trace RunAsGyro(const CarrierOptions& options, const Eigen::Matrix2cd& forcer_gain,
                const CompensationSet& p, double omega_rad_s, double turns,
                bool delay_known = true) {
  CarrierSimulation sim(options);
  const double theta0 = 0.3;
  sim.Release({{1.0, 0.0, theta0, 0.0}, omega_rad_s, 1.0 / kH, 7, 25.0, 0.0});
  sim.SetControl(forcer_gain, Eigen::Matrix2cd::Zero());
  const double turn_rate = std::abs(4.0 * options.resonator.angular_gain * omega_rad_s);
  const auto settle = static_cast<std::size_t>(1.0 / kH);
  const auto n = settle + static_cast<std::size_t>(turns * 2.0 * kPi / turn_rate / kH);
  estimator::WholeAngleLoopGains gains;
  if (delay_known) gains.measurement_delay_s = sim.group_delay_s();
  estimator::WholeAngleControl control(p, gains, kH);
  Eigen::Vector4d u = Eigen::Vector4d::Zero();
  Trace trace;
  for (std::size_t k = 0; k < n; ++k) {
    const auto sample = control.Step(sim.Observe(omega_rad_s, u));
    u = sample.u;
    if (k >= settle) {
      trace.angle_rad.push_back(sample.angle_rad);
      trace.rate_error_rad_s.push_back(sample.rate_rad_s - omega_rad_s);
      trace.max_quadrature_ratio =
          std::max(trace.max_quadrature_ratio, std::abs(sample.quadrature / sample.energy));
      trace.max_energy_error = std::max(trace.max_energy_error, std::abs(sample.energy - 1.0));
      trace.mean_effort_per_s += sample.amplitude_effort_per_s / static_cast<double>(n - settle);
    }
    sim.Advance(u);
  }
  return trace;
}

analysis::RateErrorHarmonics Harmonics(const Trace& trace) {
  auto fit = analysis::FitRateErrorHarmonics(trace.angle_rad, trace.rate_error_rad_s, kH, 100, 2);
  EXPECT_TRUE(fit.ok) << fit.why;
  return fit;
}

CompensationSet Exact(const estimator::Delta& delta) {
  CompensationSet p;
  p.delta = delta;
  return p;
}

TEST(CarrierOperatingModeTest, TheLoopsRunTheCarrierWaveAsAGyro) {
  CarrierOptions o = IdealChain();
  o.resonator.frequency_split_hz = 2e-4;
  o.resonator.frequency_axis_rad = 0.2;
  const auto trace =
      RunAsGyro(o, Eigen::Matrix2cd::Identity(), Exact(HandDelta(o.resonator)), 0.3, 2.0);
  RecordProperty("max_energy_error", Figure(trace.max_energy_error));
  RecordProperty("max_quadrature_ratio", Figure(trace.max_quadrature_ratio));
  RecordProperty("mean_effort", Figure(trace.mean_effort_per_s));
  const double turned = 2.0 * (trace.angle_rad.back() - trace.angle_rad.front());
  RecordProperty("turned", Figure(turned));
  const auto fit = Harmonics(trace);
  RecordProperty("bias", Figure(fit.bias_rad_s));
  RecordProperty("rms", Figure(fit.angle_dependent_rms_rad_s));
  EXPECT_LT(trace.max_energy_error, 1e-3);
  // The amplitude loop makes up the decay, 1/τ = 1e-3 1/s, through the forcers' hold at mid-step
  // (a gain sinc(ω·dt/2) = 0.9959 at 5 kHz, 100 kHz): g = 1e-3/0.9959.
  EXPECT_NEAR(trace.mean_effort_per_s, 1e-3 / 0.9959, 1e-6);
  EXPECT_LT(trace.max_quadrature_ratio, 1e-3);
  EXPECT_NEAR(turned, -4.0 * kPi, 0.01);
}

TEST(CarrierOperatingModeTest, TheDampingAnisotropyDriftsTheWaveAsDerived) {
  CarrierOptions o = IdealChain();
  o.resonator.damping_anisotropy_per_s = 8e-5;
  o.resonator.damping_axis_rad = -0.4;
  const estimator::Delta truth = HandDelta(o.resonator);
  auto p = Exact(truth);
  p.delta[2] = p.delta[3] = 0.0;
  for (const double omega : {0.3, -0.3}) {
    const auto fit = Harmonics(RunAsGyro(o, Eigen::Matrix2cd::Identity(), p, omega, 2.0));
    const double c = -truth[3] / (2.0 * truth[1]);
    const double s = truth[2] / (2.0 * truth[1]);
    RecordProperty("c" + std::to_string(omega), Figure(fit.cos_rad_s[0] / c - 1.0));
    RecordProperty("s" + std::to_string(omega), Figure(fit.sin_rad_s[0] / s - 1.0));
    RecordProperty("bias" + std::to_string(omega), Figure(fit.bias_rad_s));
    const double tolerance = 0.01 * std::hypot(c, s);
    EXPECT_NEAR(fit.cos_rad_s[0], c, tolerance) << "Ω = " << omega;
    EXPECT_NEAR(fit.sin_rad_s[0], s, tolerance) << "Ω = " << omega;
    const auto compensated =
        Harmonics(RunAsGyro(o, Eigen::Matrix2cd::Identity(), Exact(truth), omega, 2.0));
    RecordProperty("ratio" + std::to_string(omega),
                   Figure(fit.angle_dependent_rms_rad_s / compensated.angle_dependent_rms_rad_s));
    EXPECT_LT(compensated.angle_dependent_rms_rad_s, 1e-2 * fit.angle_dependent_rms_rad_s);
  }
}

TEST(CarrierOperatingModeTest, TheForcersGainAndAngleErrorsActAsADampingAnisotropyTimesTheEffort) {
  CarrierOptions o = IdealChain();
  const double beta1 = 2e-3, beta4 = -1e-3;
  Eigen::Matrix2cd forcer = Eigen::Matrix2cd::Identity();
  forcer(0, 0) += beta1;
  forcer(1, 1) -= beta1;
  forcer(0, 1) += beta4;
  forcer(1, 0) += beta4;
  const estimator::Delta truth = HandDelta(o.resonator);
  const double g = -truth[0];
  const auto fit = Harmonics(RunAsGyro(o, forcer, Exact(truth), 0.3, 2.0));
  const double c = -g * beta4 / (2.0 * truth[1]);
  const double s = g * beta1 / (2.0 * truth[1]);
  RecordProperty("c", Figure(fit.cos_rad_s[0] / c - 1.0));
  RecordProperty("s", Figure(fit.sin_rad_s[0] / s - 1.0));
  RecordProperty("bias", Figure(fit.bias_rad_s));
  const double tolerance = 0.01 * std::hypot(c, s);
  EXPECT_NEAR(fit.cos_rad_s[0], c, tolerance);
  EXPECT_NEAR(fit.sin_rad_s[0], s, tolerance);
}

TEST(CarrierOperatingModeTest, TheDemodulatorsDelayIsAScaleFactorAsDerivedAndTheReadoutRemovesIt) {
  const CarrierOptions o = IdealChain();
  const estimator::Delta truth = HandDelta(o.resonator);
  const double g = -truth[0];
  const double wc = 2.0 * kPi * o.electronics.filter_cutoff_hz;
  const double tau_g = 2.0 * (std::sin(kPi / 8.0) + std::sin(3.0 * kPi / 8.0)) / wc;
  for (const double omega : {0.3, -0.3}) {
    const auto blind = Harmonics(RunAsGyro(o, Eigen::Matrix2cd::Identity(), Exact(truth), omega,
                                           2.0, /*delay_known=*/false));
    const double law = -g * tau_g * omega;
    RecordProperty("blind_bias_over_law", Figure(blind.bias_rad_s / law));
    EXPECT_NEAR(blind.bias_rad_s, law, 0.01 * std::abs(law)) << "Ω = " << omega;
    const auto told =
        Harmonics(RunAsGyro(o, Eigen::Matrix2cd::Identity(), Exact(truth), omega, 2.0));
    RecordProperty("told_bias_over_law", Figure(told.bias_rad_s / law));
    EXPECT_LT(std::abs(told.bias_rad_s), 0.01 * std::abs(law)) << "Ω = " << omega;
  }
}

// The station's carrier unit (bench_configs/station-sim-carrier.toml, noise off): every pick-off
// error, a damping and a frequency split, the chain's common delay. With p = the (δ, ξ) the slow
// model sees of it (CarrierSimulation::delta, xi: estimator/pickoff_frame.hpp) the angle-dependent
// error of the factory block falls by more than 1000×; what is left is a bias: the forcers act in
// the electrode frame, which the model sees turned by the pick-off's frame angle a (c·V(a), the
// forcers' gain in the model frame, after the drive's phase trim: carrier_simulation.hpp), law 5
// with b = Re(M21 − M12)/Re(M11 + M22).
TEST(CarrierOperatingModeTest, TheExactCompensationRemovesTheAngleDependentErrorOfACarrierUnit) {
  CarrierOptions o = IdealChain();
  o.resonator.damping_anisotropy_per_s = 2e-5;
  o.resonator.damping_axis_rad = -0.4;
  o.resonator.frequency_split_hz = 2e-4;
  o.resonator.frequency_axis_rad = 0.2;
  o.pickoff.errors.gain_ratio = 0.98;
  o.pickoff.errors.phase_mismatch_rad = 0.002;
  o.pickoff.errors.cross_talk = 0.001;
  o.pickoff.errors.electrode_angle_error_rad = 0.002;
  o.pickoff.common_delay_s = 2e-6;
  CarrierSimulation seen(o);
  CompensationSet exact;
  exact.delta = seen.delta();
  exact.xi = seen.xi();
  const Eigen::Matrix2cd m = seen.forcer_gain_in_model_frame();
  const double b = (m(1, 0) - m(0, 1)).real() / (m(0, 0) + m(1, 1)).real();
  const auto untuned = estimator::IdentityCompensation(0.3, -1e-3);
  for (const double omega : {0.3, -0.3}) {
    const auto before = Harmonics(RunAsGyro(o, Eigen::Matrix2cd::Identity(), untuned, omega, 2.0));
    const auto after = Harmonics(RunAsGyro(o, Eigen::Matrix2cd::Identity(), exact, omega, 2.0));
    RecordProperty("before_over_after",
                   Figure(before.angle_dependent_rms_rad_s / after.angle_dependent_rms_rad_s));
    const double bias = -(-exact.delta[0]) * b / (2.0 * exact.delta[1]);
    RecordProperty("bias_over_law", Figure(after.bias_rad_s / bias));
    RecordProperty("b", Figure(b));
    EXPECT_LT(after.angle_dependent_rms_rad_s, 1e-3 * before.angle_dependent_rms_rad_s);
    // Law 5 to first order in b (b² and the frame angle's imaginary part: 2 %).
    EXPECT_NEAR(after.bias_rad_s, bias, 0.02 * std::abs(bias)) << "Ω = " << omega;
  }
}

}  // namespace
}  // namespace hrgbench::drivers::sim
