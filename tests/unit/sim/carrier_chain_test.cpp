// The carrier-level chain (CarrierSimulation: resonator → pick-off → electronics) against numbers
// derived independently: the Butterworth filter's gain and group delay from the analog prototype,
// the output noise from the noise bandwidth, the slow model (estimator::PropagateExact with the
// mapped δ, ξ) seen through ideal electronics, a reference offset as a phase ramp 2π·Δf_ref·t, a
// temperature ramp as the phase π·f0·α·Ṫ·t².

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "hrgbench/estimator/reference_phase.hpp"
#include "hrgbench/estimator/simulation.hpp"
#include "sim/butterworth_low_pass.hpp"
#include "sim/carrier_pickoff.hpp"
#include "sim/carrier_simulation.hpp"

namespace hrgbench::drivers::sim {
namespace {

using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;

TEST(ButterworthLowPassTest, UnityAtDcHalfPowerAtCutoffAndTheAnalogGroupDelay) {
  const double fs = 100000.0, fc = 200.0;
  ButterworthLowPass filter(4, fc, fs);
  // Analog prototype: τ(0) = Σ 1/(Q_k·ωc) = 2·(sin(π/8) + sin(3π/8))/ωc = 2.6131/ωc. The bilinear
  // transform at fc/fs = 0.002 changes it by O((fc/fs)²).
  const double analog = 2.0 * (std::sin(kPi / 8) + std::sin(3 * kPi / 8)) / (2 * kPi * fc);
  EXPECT_NEAR(filter.group_delay_s(), analog, 1e-3 * analog);
  // A ramp leaves the filter exactly one group delay late.
  Eigen::Array4d y;
  const int n = 20000;
  for (int i = 0; i < n; ++i) y = filter.Filter(Eigen::Array4d::Constant(i / fs));
  EXPECT_NEAR((n - 1) / fs - y[0], filter.group_delay_s(), 1e-9);
  // A tone at cutoff comes out at 1/√2.
  ButterworthLowPass tone(4, fc, fs);
  double peak = 0.0;
  for (int i = 0; i < 200000; ++i) {
    const double out = tone.Filter(Eigen::Array4d::Constant(std::sin(2 * kPi * fc * i / fs)))[0];
    if (i > 100000) peak = std::max(peak, std::abs(out));
  }
  EXPECT_NEAR(peak, 1.0 / std::sqrt(2.0), 1e-4);
  // Steady state: a constant in, the same constant out from the first sample.
  ButterworthLowPass settled(6, fc, fs);
  settled.SetSteadyState(Eigen::Array4d(1.0, -2.0, 3.0, 0.5));
  const Eigen::Array4d out = settled.Filter(Eigen::Array4d(1.0, -2.0, 3.0, 0.5));
  EXPECT_NEAR((out - Eigen::Array4d(1.0, -2.0, 3.0, 0.5)).abs().maxCoeff(), 0.0, 1e-14);
}

CarrierOptions TestUnit() {
  CarrierOptions o;
  o.resonator.frequency_hz = 5000.0;
  o.resonator.decay_time_s = 50.0;
  o.resonator.damping_anisotropy_per_s = 0.004;
  o.resonator.damping_axis_rad = 0.3;
  o.resonator.frequency_split_hz = 0.05;
  o.resonator.frequency_axis_rad = -0.5;
  o.resonator.angular_gain = 0.3;
  o.pickoff.errors = {1.01, 0.004, 0.002, 0.006};
  o.electronics.quantise = false;
  return o;
}

struct SimulatedRun {
  std::vector<double> t;
  std::vector<estimator::Observation> y;
};

SimulatedRun Simulate(CarrierSimulation& sim, const CarrierRelease& release, double duration_s) {
  sim.Release(release);
  SimulatedRun run;
  const int n = static_cast<int>(std::lround(duration_s * release.output_rate_hz));
  for (int k = 0; k < n; ++k) {
    run.t.push_back(k / release.output_rate_hz);
    run.y.push_back(sim.Next(release.omega_rad_s));
  }
  return run;
}

// The model's y at t, late by the filter's group delay (a delay of the slow signal; A is constant
// in a run, so it is a different x0 to the estimator).
estimator::Observation Model(const CarrierSimulation& sim, const CarrierRelease& release,
                             double t) {
  const estimator::State x = estimator::PropagateExact(
      release.omega_rad_s, sim.delta(), sim.ModelState(estimator::OrbitToState(release.orbit)),
      t - sim.group_delay_s());
  return (estimator::Matrix4::Identity() + estimator::DistortionMatrix(sim.xi())) * x;
}

constexpr double kSettle = 0.02;  // s: the filter's release transient (see README) has decayed

TEST(CarrierSimulationTest, IdealElectronicsReproduceTheSlowModel) {
  // Free-running reference exactly at f0, no path delay, no noise, no quantisation. The remaining
  // difference is the averaging error O(|A|/ω0): |A| ≈ πΔf + 2kΩ + 1/τ ≈ 0.48 1/s, /ω0 = 1.5e-5,
  // and the filter's deviation from a pure delay at |A|: (|A|/ωc)² ≈ 1.5e-7. Bound: 1e-4.
  const CarrierOptions options = TestUnit();
  CarrierSimulation sim(options);
  const CarrierRelease release{{1.0, 0.2, 0.7, 0.0}, 0.5, 1000.0, 1, 25.0, 0.0};
  const SimulatedRun run = Simulate(sim, release, 2.0);
  EXPECT_EQ(sim.decimation(), 100);
  double worst = 0.0;
  for (std::size_t k = 0; k < run.t.size(); ++k) {
    if (run.t[k] < kSettle) continue;
    worst = std::max(worst, (run.y[k] - Model(sim, release, run.t[k])).cwiseAbs().maxCoeff());
  }
  RecordProperty("worst_error", std::to_string(worst));
  EXPECT_LT(worst, 1e-4);
  // The release sample is the held wave through the pick-off: (I + C)·x0 (filters settled on it),
  // with the pick-off's own C (the split's mixing, in sim.xi(), is a property of the free modes)
  // and x0 the wave's state in the model's frame.
  const estimator::Observation y0 =
      (estimator::Matrix4::Identity() + estimator::DistortionMatrix(sim.pickoff_xi())) *
      sim.ModelState(estimator::OrbitToState(release.orbit));
  EXPECT_LT((run.y[0] - y0).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(CarrierSimulationTest, TrackingReferenceKeepsTheFormsOfTheSlowModel) {
  // A tracking PLL rotates y by a common phase, which the forms r = W(y)·y do not see.
  CarrierOptions options = TestUnit();
  options.electronics.reference.mode = ReferenceMode::kTracking;
  options.electronics.reference.pll_bandwidth_hz = 2.0;
  CarrierSimulation sim(options);
  const CarrierRelease release{{1.0, 0.2, 0.7, 0.0}, -0.3, 1000.0, 1, 25.0, 0.0};
  const SimulatedRun run = Simulate(sim, release, 2.0);
  double worst = 0.0;
  for (std::size_t k = 0; k < run.t.size(); ++k) {
    if (run.t[k] < kSettle) continue;
    const estimator::Forms r = estimator::QuadraticForms(run.y[k]);
    const estimator::Forms m = estimator::QuadraticForms(Model(sim, release, run.t[k]));
    worst = std::max(worst, (r - m).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 2e-4);  // forms are quadratic: twice the bound on y
  // ... and it did track: the reference moved off the lock frequency (the split turns the wave's
  // phase), so the phase it accumulated is not zero.
  EXPECT_GT(std::abs(sim.electronics().reference().phase_rad()), 1e-4);
}

TEST(CarrierSimulationTest, TrackingReferenceUndoneByItsReportedPhaseIsTheSlowModel) {
  // The same tracking PLL; each sample turned back by the phase the electronics report with it
  // (χ at t − τg). What is left is what a reference kept at the lock frequency gives: the slow
  // model, within the bound of IdealElectronicsReproduceTheSlowModel (1e-4; the delay-aligned χ
  // leaves χ''·τg²/2 ≈ 1e-8 besides). Without the undo the error is the wave's own phase
  // evolution that the PLL took out, far above that bound.
  CarrierOptions options = TestUnit();
  options.electronics.reference.mode = ReferenceMode::kTracking;
  options.electronics.reference.pll_bandwidth_hz = 2.0;
  CarrierSimulation sim(options);
  const CarrierRelease release{{1.0, 0.2, 0.7, 0.0}, -0.3, 1000.0, 1, 25.0, 0.0};
  sim.Release(release);
  double worst_undone = 0.0, worst_raw = 0.0;
  for (int k = 0; k < 2000; ++k) {
    const double t = k / release.output_rate_hz;
    const estimator::Observation y = sim.Next(release.omega_rad_s);
    Eigen::Matrix4Xd undone = y;
    const double chi[1] = {sim.electronics().reported_phase_rad()};
    ASSERT_TRUE(estimator::UndoReferencePhase(undone, chi));
    if (t < kSettle) continue;
    const estimator::Observation m = Model(sim, release, t);
    worst_undone = std::max(worst_undone, (undone.col(0) - m).cwiseAbs().maxCoeff());
    worst_raw = std::max(worst_raw, (y - m).cwiseAbs().maxCoeff());
  }
  RecordProperty("worst_undone", std::to_string(worst_undone));
  EXPECT_LT(worst_undone, 1e-4);
  EXPECT_GT(worst_raw, 1e-3);
  // χ is what the reference accumulated, τg late: it moved ≈ 0.3 rad in 2 s, so by ~0.2 % of
  // that in τg ≈ 3.4 ms (1 % allowed), and it is not zero.
  const double accumulated = sim.electronics().reference().phase_rad();
  EXPECT_GT(std::abs(accumulated), 0.05);
  EXPECT_NEAR(sim.electronics().reported_phase_rad(), accumulated, 0.01 * std::abs(accumulated));
}

TEST(CarrierSimulationTest, FreeRunningReferenceReportsItsOffsetRamp) {
  // A free-running reference 0.01 Hz off: χ(t) = 2π·0.01·(t − τg) once past the release.
  CarrierOptions options = TestUnit();
  options.electronics.reference.offset_hz = 0.01;
  CarrierSimulation sim(options);
  sim.Release({{1.0, 0.1, 0.2, 0.0}, 0.3, 1000.0, 1, 25.0, 0.0});
  for (int k = 0; k < 1000; ++k) {
    sim.Next(0.3);
    const double t = k / 1000.0;
    if (t < kSettle) continue;
    ASSERT_NEAR(sim.electronics().reported_phase_rad(), 2 * kPi * 0.01 * (t - sim.group_delay_s()),
                1e-9)
        << t;
  }
}

// The common phase of the simulated y relative to the model's, over a run: arg Σ conj(m)·y per
// sample (both channels).
double CommonPhase(const estimator::Observation& y, const estimator::Observation& m) {
  const Complex s = std::conj(Complex(m[0], m[1])) * Complex(y[0], y[1]) +
                    std::conj(Complex(m[2], m[3])) * Complex(y[2], y[3]);
  return std::arg(s);
}

TEST(CarrierSimulationTest, ReferenceOffsetIsACommonPhaseRamp) {
  CarrierOptions options = TestUnit();
  options.electronics.reference.offset_hz = 0.01;
  CarrierSimulation sim(options);
  const CarrierRelease release{{1.0, 0.1, 0.2, 0.0}, 0.3, 1000.0, 1, 25.0, 0.0};
  const SimulatedRun run = Simulate(sim, release, 2.0);
  for (std::size_t k = 100; k < run.t.size(); k += 300) {
    // The reference runs 0.01 Hz fast: y turns at −2π·0.01 rad/s (from the release, delayed by
    // the filter for the part after it).
    const double expected = -2 * kPi * 0.01 * (run.t[k] - sim.group_delay_s());
    EXPECT_NEAR(CommonPhase(run.y[k], Model(sim, release, run.t[k])), expected, 1e-4) << run.t[k];
  }
}

TEST(CarrierSimulationTest, TemperatureRampTurnsThePhaseQuadratically) {
  // f(T) = f0·(1 + α·(T − T0)), T = T0 + Ṫ·t: a reference left at f0 sees the phase
  // ∫2π·f0·α·Ṫ·t dt = π·f0·α·Ṫ·t² (here 0.0628 rad at 2 s).
  CarrierOptions options = TestUnit();
  options.frequency_temperature_coefficient_per_c = 1e-5;
  CarrierSimulation sim(options);
  const CarrierRelease release{{1.0, 0.1, 0.2, 0.0}, 0.3, 1000.0, 1, 25.0, 0.1};
  const SimulatedRun run = Simulate(sim, release, 2.0);
  for (std::size_t k = 500; k < run.t.size(); k += 500) {
    const double t = run.t[k] - sim.group_delay_s();
    const double expected = kPi * 5000.0 * 1e-5 * 0.1 * t * t;
    EXPECT_NEAR(CommonPhase(run.y[k], Model(sim, release, run.t[k])), expected,
                0.01 * expected + 1e-4)
        << run.t[k];
  }
}

TEST(CarrierSimulationTest, WhiteConverterNoiseComesOutThroughTheNoiseBandwidth) {
  // σ_y² = 4·σ_w²·B/fs per component: 2·w·cos ψ has variance 2σ_w², white, and the filter passes
  // 2B/fs of it (B: one-sided noise bandwidth; Butterworth N: B = fc·(π/2N)/sin(π/2N)).
  CarrierOptions quiet = TestUnit();
  CarrierOptions noisy = quiet;
  noisy.pickoff.white_noise_std = 1e-3;
  CarrierSimulation a(quiet), b(noisy);
  const CarrierRelease release{{1.0, 0.1, 0.2, 0.0}, 0.3, 1000.0, 7, 25.0, 0.0};
  const SimulatedRun clean = Simulate(a, release, 5.0);
  const SimulatedRun dirty = Simulate(b, release, 5.0);
  double sum2 = 0.0;
  int count = 0;
  for (std::size_t k = 20; k < clean.t.size(); ++k) {
    sum2 += (dirty.y[k] - clean.y[k]).squaredNorm();
    count += 4;
  }
  const double bandwidth = 200.0 * (kPi / 8) / std::sin(kPi / 8);
  const double expected = 1e-3 * std::sqrt(4.0 * bandwidth / 100000.0);
  // 19 920 values, correlated over ~1 ms: the std of the estimate is ~1 %. Tolerance 5 %.
  EXPECT_NEAR(std::sqrt(sum2 / count), expected, 0.05 * expected);
}

TEST(CarrierSimulationTest, SameSeedSameSamplesAndQuantisedToTheWire) {
  CarrierOptions options = TestUnit();
  options.pickoff.white_noise_std = 1e-3;
  options.pickoff.coloured_noise_std = 1e-3;
  options.electronics.quantise = true;
  CarrierSimulation a(options), b(options);
  const CarrierRelease release{{1.0, 0.1, 0.2, 0.0}, 0.3, 1000.0, 42, 25.0, 0.0};
  const SimulatedRun ra = Simulate(a, release, 0.2), rb = Simulate(b, release, 0.2);
  for (std::size_t k = 0; k < ra.y.size(); ++k) {
    EXPECT_EQ(ra.y[k], rb.y[k]);
    for (int c = 0; c < 4; ++c) {
      const double raw = ra.y[k][c] * 4194304.0;  // gyro_can::kSampleLsb = 2^-22
      EXPECT_EQ(raw, std::nearbyint(raw));
    }
  }
}

TEST(CarrierSimulationTest, PathDelaysRealiseThePickoffAtTheCarrier) {
  // A common delay is a common phase e^{−iω0·τ0} and a common gain a common factor: both are the
  // model's c (absorbed by x0, carried here by ModelState); the mapping's ξ is unchanged.
  CarrierOptions options = TestUnit();
  const CarrierSimulation plain(options);
  options.pickoff.common_delay_s = 3e-6;
  options.pickoff.common_gain = 1.7;
  CarrierSimulation sim(options);
  EXPECT_LT((sim.xi() - plain.xi()).cwiseAbs().maxCoeff(), 1e-15);
  const estimator::State x0(1.0, 0.0, 0.0, 0.0);
  const estimator::State plain_x0 = plain.ModelState(x0), common_x0 = sim.ModelState(x0);
  const Complex c = std::polar(1.7, -2 * kPi * 5000.0 * 3e-6);
  const Complex ratio = Complex(common_x0[0], common_x0[1]) / Complex(plain_x0[0], plain_x0[1]);
  EXPECT_LT(std::abs(ratio - c), 1e-14);
  const CarrierRelease release{{1.0, 0.2, 0.7, 0.0}, 0.5, 1000.0, 1, 25.0, 0.0};
  const SimulatedRun run = Simulate(sim, release, 0.5);
  double worst = 0.0;
  for (std::size_t k = 20; k < run.t.size(); ++k)
    worst = std::max(worst, (run.y[k] - Model(sim, release, run.t[k])).cwiseAbs().maxCoeff());
  EXPECT_LT(worst, 2e-4);  // 1.7 × the ideal bound
}

TEST(CarrierPickoffTest, ConverterNoiseHasItsStdAndCorrelation) {
  // With the oscillator at rest the channels carry the noise alone. White: std σ_w, uncorrelated;
  // AR(1): stationary std σ_c, lag-1 correlation ρ = e^{−dt/τc} (here e^{−0.1} = 0.905).
  // 200 000 samples: the std of each estimate is ~0.3 % (white), ~1 % (AR(1), 100 correlation
  // times per 1000 samples); tolerance 3 %, and 0.01 on ρ.
  estimator::ResonatorParameters resonator;
  CarrierResonator rest(resonator, 1e-5);
  for (const bool coloured : {false, true}) {
    CarrierPickoffOptions options;
    (coloured ? options.coloured_noise_std : options.white_noise_std) = 2e-3;
    options.coloured_noise_time_s = 1e-4;
    CarrierPickoff pickoff(options, resonator.frequency_hz);
    pickoff.Configure(rest);
    pickoff.Reset(5);
    const int n = 200000;
    double sum2 = 0.0, lag1 = 0.0, previous = 0.0;
    for (int i = 0; i < n; ++i) {
      const double s = pickoff.Sample(CarrierState::Zero())[0];
      sum2 += s * s;
      lag1 += s * previous;
      previous = s;
    }
    const double std = std::sqrt(sum2 / n);
    EXPECT_NEAR(std, 2e-3, 0.03 * 2e-3) << coloured;
    EXPECT_NEAR(lag1 / sum2, coloured ? std::exp(-0.1) : 0.0, 0.01) << coloured;
  }
}

TEST(CarrierOptionsTest, ValidationNamesTheField) {
  CarrierOptions o;
  std::string why;
  EXPECT_TRUE(o.IsValid(&why)) << why;
  o.sample_rate_hz = 15000.0;  // < 4·f0
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("sample_rate_hz"), std::string::npos);
  o = {};
  o.electronics.filter_order = 3;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("filter_order"), std::string::npos);
  o = {};
  o.pickoff.errors.gain_ratio = -1.0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("gain_ratio"), std::string::npos);
}

}  // namespace
}  // namespace hrgbench::drivers::sim
