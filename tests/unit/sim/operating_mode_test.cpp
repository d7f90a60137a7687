// The gyro as a gyro (issue 28 §1–§2, slow model): the simulated resonator with the control in it
// (ControlledResonator, the exact zero-order-hold discretisation of the paper's full model) run by
// the electronics' whole-angle loops and readout (WholeAngleControl) at a constant table rate. The
// rate error the readout shows is compared with the first-order laws derived in
// docs/estimator/operating-mode.md — written out in each test, not computed by the code under test:
//
//   drift of the damping anisotropy   Ω̂ − Ω = −(δ4·cos2θ − δ3·sin2θ)/(2δ2)
//   the pick-off's angle error        Ω̂ − Ω = Ω·(−2ξ1·cos2θ − 2ξ4·sin2θ)
//   the forcers' gain and angle       δ3, δ4 gain g·β1, g·β4 (g = −δ1, the energy loop's effort)
//   the forcers' frame turned by b    Ω̂ − Ω = −g·b/(2δ2), a bias
//
// Tolerances: each law drops terms of second order in the small parameters (|ξ|, |β|, drift/θ')
// and the discretisation's O(h·θ') (h = 1 ms): 2 % of the first-order amplitude where ξ ≈ 1e-2
// enters squared, 0.5 % otherwise.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "hrgbench/analysis/rate_error_harmonics.hpp"
#include "hrgbench/estimator/compensation.hpp"
#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/whole_angle_control.hpp"
#include "sim/controlled_resonator.hpp"

namespace hrgbench::drivers::sim {
namespace {

using estimator::CompensationSet;
using estimator::Delta;
using estimator::Xi;
constexpr double kH = 1e-3;  // the electronics' sample period, s
constexpr double kPi = std::numbers::pi;

// A figure for RecordProperty, to three significant digits.
std::string Figure(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

struct Trace {
  std::vector<double> angle_rad;
  std::vector<double> rate_error_rad_s;
  double max_quadrature_ratio = 0.0;  // max |K̂/Ŝ| after the settling second
  double max_energy_error = 0.0;      // max |Ŝ − 1| after it
};

// Runs the unit as a gyro for `turns` turns of 2θ at Ω (after one second of settling, not kept).
Trace RunAsGyro(const ControlledResonatorTruth& truth, const CompensationSet& p, double omega_rad_s,
                double turns) {
  const double turn_rate = std::abs(2.0 * 2.0 * truth.delta[estimator::kScaleFactor] * omega_rad_s);
  const auto settle = static_cast<std::size_t>(1.0 / kH);
  const auto n = settle + static_cast<std::size_t>(turns * 2.0 * kPi / turn_rate / kH);
  const double theta0 = 0.3;
  ControlledResonator plant(truth, omega_rad_s, kH,
                            estimator::State(std::cos(theta0), 0.0, std::sin(theta0), 0.0));
  estimator::WholeAngleControl control(p, {}, kH);
  Eigen::Vector4d u = Eigen::Vector4d::Zero();
  Trace trace;
  for (std::size_t k = 0; k < n; ++k) {
    const auto sample = control.Step(plant.Observe(u));
    u = sample.u;
    if (k >= settle) {
      trace.angle_rad.push_back(sample.angle_rad);
      trace.rate_error_rad_s.push_back(sample.rate_rad_s - omega_rad_s);
      trace.max_quadrature_ratio =
          std::max(trace.max_quadrature_ratio, std::abs(sample.quadrature / sample.energy));
      trace.max_energy_error = std::max(trace.max_energy_error, std::abs(sample.energy - 1.0));
    }
    plant.Advance(u);
  }
  return trace;
}

analysis::RateErrorHarmonics Harmonics(const Trace& trace) {
  auto fit = analysis::FitRateErrorHarmonics(trace.angle_rad, trace.rate_error_rad_s, kH, 100, 2);
  EXPECT_TRUE(fit.ok) << fit.why;
  return fit;
}

ControlledResonatorTruth Isotropic() {
  ControlledResonatorTruth truth;
  truth.delta << -1e-3, 0.3, 0.0, 0.0, 0.0, 0.0;
  return truth;
}

CompensationSet ExactCompensation(const ControlledResonatorTruth& truth) {
  CompensationSet p;
  p.delta = truth.delta;
  p.xi = truth.xi;
  return p;
}

TEST(OperatingModeTest, TheLoopsHoldTheEnergyAndNullTheQuadratureAsTheWaveTurns) {
  auto truth = Isotropic();
  truth.delta[4] = 2e-4;   // a 64 µHz frequency split at 0°
  truth.delta[5] = -1e-4;  // and at 45°
  truth.delta[2] = 3e-5;
  const auto trace = RunAsGyro(truth, ExactCompensation(truth), 0.3, 2.0);
  EXPECT_LT(trace.max_energy_error, 1e-6);
  EXPECT_LT(trace.max_quadrature_ratio, 1e-6);
  // The wave turned: 2θ over two whole turns at −4·δ2·Ω.
  const double turned = 2.0 * (trace.angle_rad.back() - trace.angle_rad.front());
  EXPECT_NEAR(turned, -4.0 * kPi, 0.01);
  // Without the split fed forward the quadrature loop alone still holds K: its error tracks the
  // split turning at 2θ' = 0.36 rad/s with a loop 20 rad/s fast.
  auto no_feed_forward = ExactCompensation(truth);
  no_feed_forward.delta[4] = no_feed_forward.delta[5] = 0.0;
  EXPECT_LT(RunAsGyro(truth, no_feed_forward, 0.3, 2.0).max_quadrature_ratio, 1e-4);
}

TEST(OperatingModeTest, TheDampingAnisotropyDriftsTheWaveAsDerived) {
  auto truth = Isotropic();
  truth.delta[2] = 3e-5;   // δ3
  truth.delta[3] = -2e-5;  // δ4
  // The electronics know everything but the drift.
  auto p = ExactCompensation(truth);
  p.delta[2] = p.delta[3] = 0.0;
  for (const double omega : {0.1, -0.3}) {
    const auto fit = Harmonics(RunAsGyro(truth, p, omega, 2.0));
    const double c = -truth.delta[3] / (2.0 * truth.delta[1]);
    const double s = truth.delta[2] / (2.0 * truth.delta[1]);
    const double tolerance = 0.005 * std::hypot(c, s);
    EXPECT_NEAR(fit.cos_rad_s[0], c, tolerance) << "Ω = " << omega;
    EXPECT_NEAR(fit.sin_rad_s[0], s, tolerance) << "Ω = " << omega;
    EXPECT_NEAR(fit.bias_rad_s, 0.0, tolerance) << "Ω = " << omega;
    // ... and p's δ3, δ4 remove it.
    const auto compensated = Harmonics(RunAsGyro(truth, ExactCompensation(truth), omega, 2.0));
    EXPECT_LT(compensated.angle_dependent_rms_rad_s, 1e-3 * fit.angle_dependent_rms_rad_s);
  }
}

TEST(OperatingModeTest, ThePickoffErrorsShowAsAnAngleDependentScaleErrorAsDerived) {
  auto truth = Isotropic();
  truth.xi << 0.01, 0.002, -0.003, 0.004;
  auto p = ExactCompensation(truth);
  p.xi.setZero();  // the electronics read y as if it were x
  for (const double omega : {0.1, -1.0}) {
    const auto fit = Harmonics(RunAsGyro(truth, p, omega, 2.0));
    const double c = -2.0 * omega * truth.xi[0];
    const double s = -2.0 * omega * truth.xi[3];
    const double tolerance = 0.02 * std::hypot(c, s);
    EXPECT_NEAR(fit.cos_rad_s[0], c, tolerance) << "Ω = " << omega;
    EXPECT_NEAR(fit.sin_rad_s[0], s, tolerance) << "Ω = " << omega;
    // Second order: the 4θ harmonic and the bias are ξ² Ω, below 2 % of the first harmonic.
    EXPECT_LT(std::hypot(fit.cos_rad_s[1], fit.sin_rad_s[1]), tolerance) << "Ω = " << omega;
    const auto compensated = Harmonics(RunAsGyro(truth, ExactCompensation(truth), omega, 2.0));
    EXPECT_LT(compensated.angle_dependent_rms_rad_s, 1e-4 * fit.angle_dependent_rms_rad_s);
  }
}

TEST(OperatingModeTest, TheForcersGainAndAngleErrorsActAsADampingAnisotropyTimesTheEffort) {
  auto truth = Isotropic();
  const double beta1 = 2e-3, beta4 = -1e-3;
  // F = I + β1·σz + β4·σx: the forcers' gain mismatch and electrode angle, as C's ξ1, ξ4.
  truth.forcer_gain(0, 0) += beta1;
  truth.forcer_gain(1, 1) -= beta1;
  truth.forcer_gain(0, 1) += beta4;
  truth.forcer_gain(1, 0) += beta4;
  const double g = -truth.delta[0];  // the energy loop's effort: it makes up the decay
  const auto fit = Harmonics(RunAsGyro(truth, ExactCompensation(truth), 0.3, 2.0));
  const double c = -g * beta4 / (2.0 * truth.delta[1]);
  const double s = g * beta1 / (2.0 * truth.delta[1]);
  const double tolerance = 0.005 * std::hypot(c, s);
  EXPECT_NEAR(fit.cos_rad_s[0], c, tolerance);
  EXPECT_NEAR(fit.sin_rad_s[0], s, tolerance);
  EXPECT_NEAR(fit.bias_rad_s, 0.0, tolerance);
}

TEST(OperatingModeTest, ForcersTurnedFromThePickoffMakeABias) {
  auto truth = Isotropic();
  const double b =
      1e-3;  // F = I + b·J: the forcers' frame turned by b (electrical) from the pick-off's
  truth.forcer_gain(0, 1) -= b;
  truth.forcer_gain(1, 0) += b;
  const double g = -truth.delta[0];
  for (const double omega : {0.3, -0.3}) {
    const auto fit = Harmonics(RunAsGyro(truth, ExactCompensation(truth), omega, 2.0));
    const double bias = -g * b / (2.0 * truth.delta[1]);
    EXPECT_NEAR(fit.bias_rad_s, bias, 0.005 * std::abs(bias)) << "Ω = " << omega;
    EXPECT_LT(fit.angle_dependent_rms_rad_s, 0.005 * std::abs(bias)) << "Ω = " << omega;
  }
}

TEST(OperatingModeTest, TheExactCompensationRemovesTheAngleDependentErrorOfAWholeUnit) {
  auto truth = Isotropic();
  truth.delta << -1e-3, 0.29, 3e-5, -2e-5, 2e-4, -1e-4;
  truth.xi << 0.01, 0.002, -0.003, 0.004;
  // Untuned: the design's angular gain and decay, nothing else.
  const auto untuned = estimator::IdentityCompensation(0.3, -1e-3);
  for (const double omega : {0.3, -0.3}) {
    const auto before = Harmonics(RunAsGyro(truth, untuned, omega, 2.0));
    const auto after = Harmonics(RunAsGyro(truth, ExactCompensation(truth), omega, 2.0));
    // The scale factor's error is not angle-dependent: it is the bias at a constant rate,
    // (0.29/0.3 − 1)·Ω before tuning.
    EXPECT_NEAR(before.bias_rad_s, (0.29 / 0.3 - 1.0) * omega, 0.02 * std::abs(omega) * 0.034);
    EXPECT_LT(after.angle_dependent_rms_rad_s, before.angle_dependent_rms_rad_s / 1e4)
        << "Ω = " << omega << ": before " << before.angle_dependent_rms_rad_s << ", after "
        << after.angle_dependent_rms_rad_s;
    EXPECT_LT(std::abs(after.bias_rad_s), 1e-9) << "Ω = " << omega;
  }
}

// The production design's free runs of a unit, from the same resonator with the control off
// (u = 0): six runs at Ω = ±0.1, ±0.3, ±1 rad/s, 100 s at 100 samples/s, θ = kπ/12.
std::vector<estimator::RunData> FreeRuns(const ControlledResonatorTruth& truth) {
  std::vector<estimator::RunData> runs;
  const double omegas[] = {0.1, -0.1, 0.3, -0.3, 1.0, -1.0};
  const double h = 0.01;
  const int n = 10000;
  for (int r = 0; r < 6; ++r) {
    auto run_truth = truth;
    run_truth.seed = truth.seed * 16 + static_cast<std::uint64_t>(r);
    const double theta = r * kPi / 12.0, b = 0.1;
    ControlledResonator plant(run_truth, omegas[r], h,
                              estimator::State(std::cos(theta), -b * std::sin(theta),
                                               std::sin(theta), b * std::cos(theta)));
    estimator::RunData run;
    run.id = r + 1;
    run.omega_rad_s = omegas[r];
    run.y.resize(4, n);
    const Eigen::Vector4d off = Eigen::Vector4d::Zero();
    for (int k = 0; k < n; ++k) {
      run.t_s.push_back(k * h);
      run.y.col(k) = plant.Observe(off);
      plant.Advance(off);
    }
    runs.push_back(std::move(run));
  }
  return runs;
}

// Issue 28's criterion on 20 units drawn around a production line's spread: estimated from their
// free runs, compensated with that estimate, verified as a gyro at 0.3 rad/s (noise-free, so that
// what is left is the estimate's error alone). The angle-dependent rate error falls by at least
// 100× on every unit, and what is left is what the estimate's covariance predicts: the first-order
// law of its (c, s) with the estimate's actual errors to 1 % (+ 1e-10 rad/s for the loops' own
// second order, 1.5e-11 with an exact p), and Σ (c, s)·Σ_pred⁻¹·(c, s)ᵀ over the units within the
// χ²(40) distribution's central 99.8 % ([17.9, 73.4]).
TEST(OperatingModeTest, TuningFromTheFreeRunsEstimateLeavesWhatItsCovariancePredicts) {
  std::mt19937_64 draw(28);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const double omega = 0.3;
  double chi_square = 0.0;
  double worst_ratio = std::numeric_limits<double>::infinity();
  for (int u = 0; u < 20; ++u) {
    ControlledResonatorTruth truth;
    truth.delta << -1e-3 * (1.0 + 0.2 * unit(draw)), 0.295 + 0.015 * unit(draw), 5e-5 * unit(draw),
        5e-5 * unit(draw), 3e-4 * unit(draw), 3e-4 * unit(draw);
    for (int i = 0; i < 4; ++i) truth.xi[i] = 1e-2 * unit(draw);
    truth.sigma = 1e-4;
    truth.seed = static_cast<std::uint64_t>(100 + u);
    estimator::MlOptions options;
    options.num_threads = 1;
    const auto estimate = estimator::EstimateMaximumLikelihood(FreeRuns(truth), options);
    ASSERT_TRUE(estimate.Converged()) << "unit " << u << ": " << estimate.message;
    CompensationSet p;
    ASSERT_TRUE(estimator::CompensationFromEstimate(estimate, &p)) << "unit " << u;

    auto verification = truth;
    verification.sigma = 0.0;
    const auto before =
        Harmonics(RunAsGyro(verification, estimator::IdentityCompensation(0.3, -1e-3), omega, 2.0));
    const auto after = Harmonics(RunAsGyro(verification, p, omega, 2.0));
    EXPECT_LT(after.angle_dependent_rms_rad_s, before.angle_dependent_rms_rad_s / 100.0)
        << "unit " << u;
    worst_ratio =
        std::min(worst_ratio, before.angle_dependent_rms_rad_s / after.angle_dependent_rms_rad_s);

    const double two_gain = 2.0 * truth.delta[1];
    const double c =
        -(truth.delta[3] - p.delta[3]) / two_gain - 2.0 * omega * (truth.xi[0] - p.xi[0]);
    const double s =
        (truth.delta[2] - p.delta[2]) / two_gain - 2.0 * omega * (truth.xi[3] - p.xi[3]);
    EXPECT_NEAR(after.cos_rad_s[0], c, 0.01 * std::hypot(c, s) + 1e-10) << "unit " << u;
    EXPECT_NEAR(after.sin_rad_s[0], s, 0.01 * std::hypot(c, s) + 1e-10) << "unit " << u;

    const Eigen::Matrix2d predicted =
        estimator::PredictedRateErrorCovariance(p, omega).bottomRightCorner<2, 2>();
    const Eigen::Vector2d measured(after.cos_rad_s[0], after.sin_rad_s[0]);
    chi_square += measured.dot(predicted.ldlt().solve(measured));
  }
  RecordProperty("chi_square_40", Figure(chi_square));
  RecordProperty("smallest_before_over_after", Figure(worst_ratio));
  EXPECT_GT(chi_square, 17.9);
  EXPECT_LT(chi_square, 73.4);
}

// A unit drawn around a production line's spread (as above).
ControlledResonatorTruth DrawUnit(std::mt19937_64& draw, std::uint64_t seed) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  ControlledResonatorTruth truth;
  truth.delta << -1e-3 * (1.0 + 0.2 * unit(draw)), 0.295 + 0.015 * unit(draw), 5e-5 * unit(draw),
      5e-5 * unit(draw), 3e-4 * unit(draw), 3e-4 * unit(draw);
  for (int i = 0; i < 4; ++i) truth.xi[i] = 1e-2 * unit(draw);
  truth.sigma = 1e-4;
  truth.seed = seed;
  return truth;
}

// Issue 28 §4: what free runs cannot see. Units whose forcers have a gain mismatch and electrode
// angle (β1, β4: 2e-3 in all, at a random angle) and a frame turned from the pick-off's (b = ±1e-3)
// drift and bias as a gyro by 3.3e-6 and 1.7e-6 rad/s however well their free runs are fitted.
// A verification of eight turns at each of ±0.3 rad/s, with the pick-off's noise, read with p
// (bias and harmonics of the integrated error), refines p's drift and bias; checked noise-free at
// ±0.3 rad/s the bias falls at least 4× further on every unit, the angle-dependent RMS on every
// unit and 4× over the units (13× measured: what is left is mostly ξ̂'s error, 2Ω·Δξ, which the
// holds' slopes only halve), and at 0.5 rad/s, a rate
// the holds did not visit, the (b, c, s) left are what the refined covariance predicts:
// Σ (b, c, s)·Σ_pred⁻¹·(b, c, s)ᵀ over 10 units within the χ²(30) distribution's central 99.8 %
// ([11.5, 59.8], Wilson–Hilferty); the slopes' check of ξ̂1, ξ̂4 within 4 std.
TEST(OperatingModeTest, AVerificationOnTheTableRemovesWhatFreeRunsCannotSee) {
  std::mt19937_64 draw(284);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * kPi);
  double chi_square = 0.0, squares_before = 0.0, squares_after = 0.0;
  for (int u = 0; u < 10; ++u) {
    auto truth = DrawUnit(draw, static_cast<std::uint64_t>(300 + u));
    const double phi = angle(draw);
    const double beta1 = 2e-3 * std::cos(phi), beta4 = 2e-3 * std::sin(phi);
    const double b = (u % 2 == 0 ? 1.0 : -1.0) * 1e-3;
    truth.forcer_gain(0, 0) += beta1;
    truth.forcer_gain(1, 1) -= beta1;
    truth.forcer_gain(0, 1) += beta4 - b;
    truth.forcer_gain(1, 0) += beta4 + b;
    estimator::MlOptions options;
    options.num_threads = 1;
    const auto estimate = estimator::EstimateMaximumLikelihood(FreeRuns(truth), options);
    ASSERT_TRUE(estimate.Converged()) << "unit " << u << ": " << estimate.message;
    CompensationSet p;
    ASSERT_TRUE(estimator::CompensationFromEstimate(estimate, &p));

    std::vector<estimator::VerificationHold> holds;
    for (const double omega : {0.3, -0.3}) {
      auto hold_truth = truth;
      hold_truth.seed = truth.seed * 16 + (omega > 0 ? 7 : 8);
      const auto fit = Harmonics(RunAsGyro(hold_truth, p, omega, 8.0));
      holds.push_back({omega, fit.bias_rad_s, fit.bias_std_rad_s, fit.cos_rad_s[0],
                       fit.cos_std_rad_s[0], fit.sin_rad_s[0], fit.sin_std_rad_s[0]});
    }
    estimator::CompensationRefinement refinement;
    ASSERT_TRUE(estimator::RefineCompensation(p, holds, &refinement)) << "unit " << u;
    const CompensationSet& refined = refinement.refined;
    EXPECT_NEAR(refinement.slope_check[0], truth.xi[0] - p.xi[0],
                4.0 * refinement.slope_check_std[0])
        << "unit " << u;
    EXPECT_NEAR(refinement.slope_check[1], truth.xi[3] - p.xi[3],
                4.0 * refinement.slope_check_std[1])
        << "unit " << u;

    auto check = truth;
    check.sigma = 0.0;
    for (const double omega : {0.3, -0.3}) {
      const auto before = Harmonics(RunAsGyro(check, p, omega, 2.0));
      const auto after = Harmonics(RunAsGyro(check, refined, omega, 2.0));
      EXPECT_LT(after.angle_dependent_rms_rad_s, before.angle_dependent_rms_rad_s)
          << "unit " << u << ", Ω = " << omega;
      EXPECT_LT(std::abs(after.bias_rad_s), std::abs(before.bias_rad_s) / 4.0)
          << "unit " << u << ", Ω = " << omega;
      squares_before += std::pow(before.angle_dependent_rms_rad_s, 2);
      squares_after += std::pow(after.angle_dependent_rms_rad_s, 2);
    }
    // Out of sample: at a rate the holds did not visit.
    const double omega = 0.5;
    const auto after = Harmonics(RunAsGyro(check, refined, omega, 2.0));
    const Eigen::Matrix3d predicted = estimator::PredictedRateErrorCovariance(refined, omega);
    const Eigen::Vector3d measured(after.bias_rad_s, after.cos_rad_s[0], after.sin_rad_s[0]);
    chi_square += measured.dot(predicted.ldlt().solve(measured));
  }
  RecordProperty("rms_before_rad_s", Figure(std::sqrt(squares_before / 20.0)));
  RecordProperty("rms_after_rad_s", Figure(std::sqrt(squares_after / 20.0)));
  RecordProperty("chi_square_30", Figure(chi_square));
  EXPECT_LT(std::sqrt(squares_after), std::sqrt(squares_before) / 4.0);
  EXPECT_GT(chi_square, 11.5);
  EXPECT_LT(chi_square, 59.8);
}

}  // namespace
}  // namespace hrgbench::drivers::sim
