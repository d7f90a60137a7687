// The engineering quantities against physics, not against their formulas: free runs of the 2-DOF
// oscillator at its carrier (CarrierResonator, exact in time, no slow model), demodulated ideally,
// are fitted by the estimator; the quantities from the fit must equal what the simulated wave
// itself shows, measured here from the wave alone:
//   - with only a frequency split, a wave released on the frequency axis stays there (its angle,
//     halved, is the axis on the shell) and one released between the axes beats at Δf (the
//     zero crossings of its quadrature K);
//   - with only a damping split, waves released on the two damping axes decay at the two rates
//     (the slope of ln S);
//   - with an isotropic resonator at Ω the wave turns on the shell at −k·Ω relative to the case.
// Tolerances: the averaging onto the slow variables is exact to O(|A|/ω0) ≈ 1e-4 here
// (physical_parameters.hpp), so the fitted quantities agree with the measured ones to ~1e-4
// relative; the measurements from zero crossings and slopes are accurate to ~1e-5.

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "hrgbench/estimator/engineering_quantities.hpp"
#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/model.hpp"
#include "hrgbench/estimator/physical_parameters.hpp"
#include "sim/carrier_resonator.hpp"

namespace hrgbench::drivers::sim {
namespace {

using Complex = std::complex<double>;
using estimator::EngineeringQuantity;
constexpr double kPi = std::numbers::pi;
constexpr double kF0 = 2000.0;
constexpr double kRate = 20.0;  // output samples per second
constexpr double kDegPerRad = 180.0 / kPi;

struct PhysicalRun {
  double omega_rad_s = 0.0;
  estimator::Orbit release;
  double duration_s = 60.0;
};

// One free run of the oscillator, demodulated at ω0 = 2π·f0 (u·e^{iω0t} = q − i·q̇/ω0), sampled at
// kRate: the slow variables x = (Re u1, Im u1, Re u2, Im u2) the pick-offs would see with no error.
estimator::RunData Simulate(const estimator::ResonatorParameters& resonator, const PhysicalRun& run,
                            int id) {
  CarrierResonator oscillator(resonator, 1.0 / kRate);
  oscillator.SetConditions(run.omega_rad_s, 1.0);
  oscillator.Release(run.release);
  const double w0 = oscillator.velocity_scale_rad_s();
  const int n = static_cast<int>(std::lround(run.duration_s * kRate));
  estimator::RunData data;
  data.id = id;
  data.omega_rad_s = run.omega_rad_s;
  data.y.resize(4, n);
  for (int k = 0; k < n; ++k) {
    const double t = k / kRate;
    const CarrierState& x = oscillator.state();
    const Complex rotation = std::polar(1.0, -w0 * t);
    const Complex u1 = Complex(x[0], -x[2]) * rotation, u2 = Complex(x[1], -x[3]) * rotation;
    data.t_s.push_back(t);
    data.y.col(k) << u1.real(), u1.imag(), u2.real(), u2.imag();
    oscillator.Step();
  }
  return data;
}

estimator::Forms FormsAt(const estimator::RunData& run, int k) {
  return estimator::QuadraticForms(run.y.col(k));
}

// The wave angle on the shell, degrees: half the model's θ.
double ShellAngleDeg(const estimator::RunData& run, int k) {
  return 0.5 * estimator::StateToOrbit(run.y.col(k)).theta_rad * kDegPerRad;
}

// Fits all runs (Ω known exactly, all of δ and ξ free) and returns the quantities.
estimator::EngineeringQuantities Fit(const std::vector<estimator::RunData>& runs) {
  const estimator::EstimateSummary s = estimator::EstimateMaximumLikelihood(runs);
  EXPECT_TRUE(s.IsUsable()) << s.Report();
  return estimator::ComputeEngineeringQuantities(s, kF0);
}

// Runs at five rates (two at Ω = 0 released where the measurement wants them), so that δ2 and ξ
// are identifiable as on the bench.
std::vector<PhysicalRun> Plan(double theta_a_rad, double theta_b_rad) {
  return {{0.0, {1.0, 0.0, theta_a_rad, 0.0}}, {0.0, {1.0, 0.0, theta_b_rad, 0.0}},
          {0.3, {1.0, 0.1, 0.3, 0.0}},         {-0.3, {1.0, -0.1, 0.9, 0.0}},
          {1.0, {1.0, 0.1, -0.4, 0.0}},        {-1.0, {1.0, -0.1, 1.2, 0.0}}};
}

TEST(EngineeringPhysicsTest, AFrequencySplitHoldsAWaveOnItsAxisAndBeatsOffIt) {
  estimator::ResonatorParameters r;
  r.frequency_hz = kF0;
  r.decay_time_s = 300.0;
  r.frequency_split_hz = 0.05;
  r.frequency_axis_rad = 2.0 * 10.0 / kDegPerRad;  // 10° on the shell
  r.angular_gain = 0.3;
  const double on_axis = r.frequency_axis_rad, between = on_axis + kPi / 4;  // 22.5° off on shell
  std::vector<estimator::RunData> runs;
  int id = 1;
  for (const PhysicalRun& p : Plan(on_axis, between)) runs.push_back(Simulate(r, p, id++));

  // On the axis the wave stays: its angle on the shell is 10° throughout.
  const estimator::RunData& held = runs[0];
  for (int k = 0; k < held.size(); k += 100) EXPECT_NEAR(ShellAngleDeg(held, k), 10.0, 1e-3);

  // Between the axes it beats: K = 2ab changes sign every 1/(2Δf); Δf from the first and last
  // zero crossings (linear interpolation).
  const estimator::RunData& beating = runs[1];
  std::vector<double> crossings;
  for (int k = 1; k < beating.size(); ++k) {
    const double k0 = FormsAt(beating, k - 1)[estimator::kK],
                 k1 = FormsAt(beating, k)[estimator::kK];
    if (k0 != 0.0 && (k0 < 0.0) != (k1 < 0.0))
      crossings.push_back(beating.t_s[k - 1] +
                          (beating.t_s[k] - beating.t_s[k - 1]) * k0 / (k0 - k1));
  }
  ASSERT_GE(crossings.size(), 4u);
  const double measured_split_hz =
      static_cast<double>(crossings.size() - 1) / (2.0 * (crossings.back() - crossings.front()));
  EXPECT_NEAR(measured_split_hz, 0.05, 1e-5);

  const estimator::EngineeringQuantities e = Fit(runs);
  EXPECT_NEAR(e[EngineeringQuantity::kFrequencySplit].value, 1e3 * measured_split_hz, 1e-4 * 50.0);
  EXPECT_NEAR(e[EngineeringQuantity::kFrequencyAxis].value, ShellAngleDeg(held, 0), 1e-3);
  EXPECT_TRUE(e[EngineeringQuantity::kFrequencyAxis].determined);
  // None set; the averaging leaves ~1e-7 1/s (3e-5 of 1/τ) in a fit of noise-free carrier data.
  EXPECT_NEAR(e[EngineeringQuantity::kDampingSplit].value, 0.0, 3e-4 / 300.0);
  EXPECT_NEAR(e[EngineeringQuantity::kDecayTime].value, 300.0, 300.0 * 1e-4);
}

TEST(EngineeringPhysicsTest, ADampingSplitDecaysTheTwoAxesAtTheirOwnRates) {
  estimator::ResonatorParameters r;
  r.frequency_hz = kF0;
  r.decay_time_s = 50.0;
  r.damping_anisotropy_per_s = 0.02;              // axes decay at 0.03 and 0.01 1/s
  r.damping_axis_rad = 2.0 * -15.0 / kDegPerRad;  // −15° on the shell
  r.angular_gain = 0.3;
  const double fast_axis = r.damping_axis_rad, slow_axis = fast_axis + kPi / 2;  // 45° on shell
  std::vector<estimator::RunData> runs;
  int id = 1;
  for (const PhysicalRun& p : Plan(fast_axis, slow_axis)) runs.push_back(Simulate(r, p, id++));

  // The amplitude decay rate of each run from the slope of ln S = ln(a² + b²) (S ∝ e^{−2t/τ_i}).
  const auto decay_rate = [](const estimator::RunData& run) {
    const int last = static_cast<int>(run.size()) - 1;
    return -0.5 * std::log(FormsAt(run, last)[estimator::kS] / FormsAt(run, 0)[estimator::kS]) /
           run.t_s[last];
  };
  const double fast = decay_rate(runs[0]), slow = decay_rate(runs[1]);
  EXPECT_NEAR(fast, 0.03, 1e-6);
  EXPECT_NEAR(slow, 0.01, 1e-6);

  const estimator::EngineeringQuantities e = Fit(runs);
  EXPECT_NEAR(e[EngineeringQuantity::kFastModeDecayTime].value, 1.0 / fast, 1e-4 / fast);
  EXPECT_NEAR(e[EngineeringQuantity::kSlowModeDecayTime].value, 1.0 / slow, 1e-4 / slow);
  EXPECT_NEAR(e[EngineeringQuantity::kDampingSplit].value, fast - slow, 1e-4 * (fast - slow));
  EXPECT_NEAR(e[EngineeringQuantity::kDampingAxis].value, ShellAngleDeg(runs[0], 0), 1e-2);
  EXPECT_NEAR(e[EngineeringQuantity::kDecayTime].value, 2.0 / (fast + slow), 1e-4 * 50.0);
  EXPECT_NEAR(e[EngineeringQuantity::kQualityFactor].value, kPi * kF0 * 2.0 / (fast + slow),
              1e-4 * kPi * kF0 * 50.0);
  EXPECT_NEAR(e[EngineeringQuantity::kFrequencySplit].value, 0.0, 1e-3);
}

TEST(EngineeringPhysicsTest, TheWaveTurnsOnTheShellAtMinusKOmega) {
  estimator::ResonatorParameters r;
  r.frequency_hz = kF0;
  r.decay_time_s = 200.0;
  r.angular_gain = 0.29;
  std::vector<estimator::RunData> runs;
  int id = 1;
  for (const PhysicalRun& p : Plan(0.2, 0.7)) runs.push_back(Simulate(r, p, id++));
  // Run 5 is at Ω = +1 rad/s: its angle on the shell over 1 s (short enough not to wrap).
  const estimator::RunData& turning = runs[4];
  ASSERT_DOUBLE_EQ(turning.omega_rad_s, 1.0);
  const int one_second = static_cast<int>(kRate);
  const double turned_deg = ShellAngleDeg(turning, one_second) - ShellAngleDeg(turning, 0);
  const double measured_k = -turned_deg / kDegPerRad / (turning.omega_rad_s * 1.0);
  EXPECT_NEAR(measured_k, 0.29, 1e-4);  // the wave lags the case: k > 0 turns it backwards

  const estimator::EngineeringQuantities e = Fit(runs);
  EXPECT_NEAR(e[EngineeringQuantity::kAngularGain].value, measured_k, 1e-4);
  EXPECT_GT(e[EngineeringQuantity::kAngularGain].value, 0.0);
}

}  // namespace
}  // namespace hrgbench::drivers::sim
