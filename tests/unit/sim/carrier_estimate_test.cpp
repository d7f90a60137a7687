// The ML estimator on carrier-level data (drivers/sim's CarrierSimulation: the 2-DOF oscillator at
// 5 kHz, the pick-off, the reference, I/Q demodulation, the Butterworth, decimation, the wire's
// quantisation), the production design shortened to 5 s runs: a tracking reference undone by the
// phase the electronics report, a tracking reference NOT reported (flagged by the fit's
// diagnostics), and the Monte Carlo of the reported std against the scatter over seeds.
// benchmarks/carrier_accuracy_table.cpp prints the same at full size (--seeds).
//
// The converter noise behind the 200 Hz filter sampled at 1 kHz is coloured (lag-1 correlation
// 0.71). Fitted as white noise a clean session fails its checks (Ljung–Box z ≈ 80; the noise from
// 4th differences sees only the high-frequency part: residual ratio ≈ 5.7); fitted with the
// filter declared, as the bench does with [gyro] output_filter (estimator/noise_shape.hpp), it
// passes them. Both are tested below.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "hrgbench/estimator/fit_diagnostics.hpp"
#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/noise_shape.hpp"
#include "hrgbench/estimator/reference_phase.hpp"
#include "sim/carrier_simulation.hpp"

namespace hrgbench::drivers::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRunS = 5.0;
constexpr double kRateHz = 1000.0;

// The unit of bench_configs/station-sim-carrier.toml (as benchmarks/carrier_accuracy_table.cpp),
// white converter noise 1.1e-3 → σ_y ≈ 1e-4 behind the 200 Hz 4th-order filter.
CarrierOptions Unit() {
  CarrierOptions o;
  o.resonator.frequency_hz = 5000.0;
  o.resonator.decay_time_s = 1000.0;
  o.resonator.damping_anisotropy_per_s = 2e-5;
  o.resonator.damping_axis_rad = -0.4;
  o.resonator.frequency_split_hz = 2e-4;
  o.resonator.frequency_axis_rad = 0.2;
  o.resonator.angular_gain = 0.3;
  o.pickoff.errors = {0.98, 0.002, 0.001, 0.002};
  o.pickoff.white_noise_std = 1.1e-3;
  return o;
}

CarrierOptions Tracking() {
  CarrierOptions o = Unit();
  o.electronics.reference.mode = ReferenceMode::kTracking;
  o.electronics.reference.pll_bandwidth_hz = 2.0;
  return o;
}

// The production design's 6 runs (Ω = ±0.1, ±0.3, ±1 rad/s, θ = kπ/12, b = 0, 0.1, 0.2), each
// turned back by the reported reference phase when `undo`.
std::vector<estimator::RunData> Session(const CarrierOptions& options, std::uint64_t seed,
                                        bool undo, double temperature_rate_c_per_s = 0.0) {
  const double omegas[6] = {0.1, -0.1, 0.3, -0.3, 1.0, -1.0};
  const double bs[6] = {0.0, 0.1, 0.2, 0.0, 0.1, 0.2};
  CarrierSimulation sim(options);
  std::vector<estimator::RunData> runs;
  const int n = static_cast<int>(std::lround(kRunS * kRateHz));
  for (int r = 0; r < 6; ++r) {
    sim.Release({{1.0, bs[r], r * kPi / 12.0, 0.0},
                 omegas[r],
                 kRateHz,
                 seed + r,
                 25.0,
                 temperature_rate_c_per_s});
    estimator::RunData run;
    run.id = r + 1;
    run.omega_rad_s = omegas[r];
    run.y.resize(4, n);
    std::vector<double> chi(n);
    for (int k = 0; k < n; ++k) {
      run.t_s.push_back(k / kRateHz);
      run.y.col(k) = sim.Next(omegas[r]);
      chi[k] = sim.electronics().reported_phase_rad();
    }
    if (undo) {
      EXPECT_TRUE(estimator::UndoReferencePhase(run.y, chi));
    }
    runs.push_back(std::move(run));
  }
  return runs;
}

// The production fit with the chain's output filter declared (4th order, 200 Hz: CarrierOptions'
// defaults), as a station declaring it records it.
estimator::MlOptions Production() {
  estimator::MlOptions ml;
  ml.num_threads = 1;
  const CarrierElectronicsOptions electronics;
  ml.noise_shape = *estimator::ButterworthNoiseShape(electronics.filter_order,
                                                     electronics.filter_cutoff_hz, kRateHz);
  return ml;
}

// Four channels of the chain's noise alone: the resonator at rest (amplitude 0).
Eigen::Matrix4Xd ChainNoise(int samples, std::uint64_t seed) {
  CarrierSimulation sim(Unit());
  sim.Release({{0.0, 0.0, 0.0, 0.0}, 0.0, kRateHz, seed, 25.0, 0.0});
  Eigen::Matrix4Xd y(4, samples);
  for (int k = 0; k < samples; ++k) y.col(k) = sim.Next(0.0);
  return y;
}

Eigen::Matrix<double, 10, 1> Truth(const CarrierOptions& options) {
  const CarrierSimulation sim(options);
  Eigen::Matrix<double, 10, 1> truth;
  truth << sim.delta(), sim.xi();
  return truth;
}

TEST(CarrierEstimateTest, ChainNoiseHasTheDeclaredFiltersAutocorrelation) {
  // The chain's filter is biquads at 100 kHz (bilinear, pre-warped) fed with demodulated converter
  // noise and decimated by 100; the declared shape is the closed form of the analog Butterworth.
  // The sample autocorrelation over 4 × 100 000 values has a standard error below 0.004 at
  // these lags (Bartlett, Σρ² ≈ 2.6): held to 0.015.
  const Eigen::Matrix4Xd y = ChainNoise(100000, 11);
  const estimator::NoiseShape shape = Production().noise_shape;
  const Eigen::Index n = y.cols();
  const Eigen::Vector4d mean = y.rowwise().mean();
  const Eigen::Matrix4Xd centred = y.colwise() - mean;
  const double c0 = centred.squaredNorm();
  for (int lag = 1; lag <= 8; ++lag) {
    const double c = (centred.leftCols(n - lag).array() * centred.rightCols(n - lag).array()).sum();
    EXPECT_NEAR(c / c0, shape.Rho(lag), 0.015) << "lag " << lag;
  }
  // σ from the data under the declared shape equals the plain std; assumed white it is ~6× low.
  const double sigma = std::sqrt(c0 / (4.0 * static_cast<double>(n)));
  EXPECT_NEAR(estimator::DifferenceNoiseSigma(y, estimator::DifferenceNoiseModelFor(shape)), sigma,
              0.01 * sigma);
  EXPECT_LT(estimator::DifferenceNoiseSigma(y), 0.3 * sigma);
}

TEST(CarrierEstimateTest, CleanSessionPassesItsChecksWithTheFilterDeclared) {
  // The finding of issue 8: a clean carrier session was always flagged. With the filter declared
  // every check passes; declared white (a station that does not say what its electronics do) it
  // is flagged on every run, naming the residual ratio and the whiteness.
  const std::vector<estimator::RunData> runs = Session(Unit(), 21, /*undo=*/false);
  const estimator::EstimateSummary declared =
      estimator::EstimateMaximumLikelihood(runs, Production());
  ASSERT_TRUE(declared.IsUsable()) << declared.message;
  EXPECT_TRUE(declared.diagnostics.Acceptable())
      << (declared.diagnostics.problems.empty() ? "" : declared.diagnostics.problems.front());
  EXPECT_EQ(declared.diagnostics.covariance_kind, "sandwich");
  for (const estimator::RunFitDiagnostics& run : declared.diagnostics.runs) {
    EXPECT_LT(run.residual_ratio, run.residual_ratio_threshold) << "run " << run.run_id;
    EXPECT_LT(run.whiteness_z, 6.0) << "run " << run.run_id;
  }
  estimator::MlOptions white = Production();
  white.noise_shape = {};
  const estimator::EstimateSummary undeclared = estimator::EstimateMaximumLikelihood(runs, white);
  ASSERT_TRUE(undeclared.IsUsable()) << undeclared.message;
  int ratio = 0, whiteness = 0;
  for (const std::string& p : undeclared.diagnostics.problems) {
    if (p.find("residual RMS") != std::string::npos) ++ratio;
    if (p.find("not white") != std::string::npos) ++whiteness;
  }
  EXPECT_EQ(ratio, 6);
  EXPECT_EQ(whiteness, 6);
}

TEST(CarrierEstimateTest, TrackingReferenceWithItsReportedPhaseUndoneEstimatesTheTruth) {
  // Every parameter within 4 of its reported std (a 6e-5 chance per parameter for an honest std;
  // before the undo the errors were ~4e3 std, benchmarks/carrier_accuracy_table).
  const CarrierOptions options = Tracking();
  const estimator::EstimateSummary s =
      estimator::EstimateMaximumLikelihood(Session(options, 7, /*undo=*/true), Production());
  ASSERT_TRUE(s.IsUsable()) << s.message;
  const Eigen::Matrix<double, 10, 1> truth = Truth(options);
  for (int j = 0; j < 6; ++j) EXPECT_LT(std::abs(s.delta[j] - truth[j]), 4 * s.delta_std[j]) << j;
  for (int j = 0; j < 4; ++j) EXPECT_LT(std::abs(s.xi[j] - truth[6 + j]), 4 * s.xi_std[j]) << j;
  // ... and the fit explains the data as well as on the same session with the reference kept
  // locked (free-running): each run's residual ratio within 2 % of that one's (the ratio's own
  // scatter is 0.451/√(4·5000) = 0.3 %, the noise realisations are the same).
  const estimator::EstimateSummary locked =
      estimator::EstimateMaximumLikelihood(Session(Unit(), 7, /*undo=*/false), Production());
  ASSERT_TRUE(locked.IsUsable()) << locked.message;
  ASSERT_EQ(s.diagnostics.runs.size(), locked.diagnostics.runs.size());
  for (std::size_t r = 0; r < s.diagnostics.runs.size(); ++r) {
    EXPECT_NEAR(s.diagnostics.runs[r].residual_ratio, locked.diagnostics.runs[r].residual_ratio,
                0.02 * locked.diagnostics.runs[r].residual_ratio)
        << "run " << r + 1;
  }
}

TEST(CarrierEstimateTest, TrackingReferenceNotReportedIsFlagged) {
  // Older electronics: the PLL tracked but its phase is not in the record. The fit cannot be
  // right (the wave's phase evolution the PLL took out is no polynomial), and it says so: every
  // run is named in a problem, and the runs at |Ω| = 1 rad/s (where the wave's
  // phase moves most) leave a residual RMS more than twice the noise (the σ̂ of the same session
  // with the phase undone), i.e. a residual ratio more than twice the clean session's.
  const estimator::EstimateSummary s =
      estimator::EstimateMaximumLikelihood(Session(Tracking(), 7, /*undo=*/false), Production());
  const estimator::EstimateSummary undone =
      estimator::EstimateMaximumLikelihood(Session(Tracking(), 7, /*undo=*/true), Production());
  ASSERT_TRUE(s.IsUsable()) << s.message;
  ASSERT_TRUE(undone.IsUsable()) << undone.message;
  EXPECT_FALSE(s.diagnostics.Acceptable());
  // Every run is named in a problem (its residual RMS or its whiteness).
  for (int run = 1; run <= 6; ++run) {
    bool named = false;
    for (const std::string& problem : s.diagnostics.problems)
      named = named || problem.rfind("run " + std::to_string(run) + ":", 0) == 0;
    EXPECT_TRUE(named) << "run " << run << "\n" << s.Report();
  }
  ASSERT_EQ(s.diagnostics.runs.size(), 6u);
  for (const std::size_t r : {std::size_t{4}, std::size_t{5}}) {  // Ω = +1, −1 rad/s
    EXPECT_GT(s.diagnostics.runs[r].residual_rms, 2.0 * undone.noise_sigma) << "run " << r + 1;
    EXPECT_GT(s.diagnostics.runs[r].residual_ratio, 2.0 * undone.diagnostics.runs[r].residual_ratio)
        << "run " << r + 1;
  }
}

TEST(CarrierEstimateTest, FrequencySplitMixesTheShapesAsDerived) {
  // Noise-free, Δf = 1 Hz at θ_ω = 0.2, ideal pick-off: the fit's ξ1, ξ4 are not 0 but
  // −(δ5, δ6)/(2ω0) = −(4.61e-5, 1.95e-5) (estimator/split_coriolis_mixing.hpp), which
  // CarrierSimulation::xi() includes. Held to 1.5e-6 (3 %), 30 times below the term; the
  // pick-off's own ξ (0) is 30 tolerances away, and every δ is within 1e-6 of the truth.
  CarrierOptions options = Unit();
  options.pickoff.white_noise_std = 0.0;
  options.pickoff.errors = {};
  options.resonator.frequency_split_hz = 1.0;
  const CarrierSimulation sim(options);
  EXPECT_EQ(sim.pickoff_xi(), estimator::Xi::Zero());
  EXPECT_NEAR(sim.xi()[0], -4.605e-5, 1e-8);
  EXPECT_NEAR(sim.xi()[3], -1.947e-5, 1e-8);
  const estimator::EstimateSummary s =
      estimator::EstimateMaximumLikelihood(Session(options, 1, /*undo=*/false), Production());
  ASSERT_TRUE(s.IsUsable()) << s.message;
  for (int j = 0; j < 4; ++j) EXPECT_NEAR(s.xi[j], sim.xi()[j], 1.5e-6) << "xi" << j + 1;
  for (int j = 0; j < 6; ++j) EXPECT_NEAR(s.delta[j], sim.delta()[j], 1e-6) << "delta" << j + 1;
}

TEST(CarrierEstimateTest, TemperatureRampMovesTheDecayRateAsDerived) {
  // Noise-free, f drifting at α·Ṫ = 5e-5/°C × 0.01 °C/s: the displacement's amplitude falls at
  // ½·ω̇/ω = 2.5e-7 1/s besides its damping (estimator/frequency_drift_decay.hpp), which
  // CarrierSimulation::delta() includes for such a release. Held to 3e-8 (12 % of the term); the
  // resonator's own −1/τ is 8 tolerances away.
  CarrierOptions options = Unit();
  options.pickoff.white_noise_std = 0.0;
  options.frequency_temperature_coefficient_per_c = 5e-5;
  CarrierSimulation sim(options);
  sim.Release({{1.0, 0.0, 0.0, 0.0}, 0.0, kRateHz, 1, 25.0, 0.01});
  EXPECT_NEAR(sim.delta()[0], -1e-3 - 2.5e-7, 1e-12);
  const estimator::EstimateSummary s =
      estimator::EstimateMaximumLikelihood(Session(options, 1, /*undo=*/false, 0.01), Production());
  ASSERT_TRUE(s.IsUsable()) << s.message;
  EXPECT_NEAR(s.delta[0], sim.delta()[0], 3e-8);
}

TEST(CarrierEstimateTest, ReportedStdMatchesTheScatterOverSeeds) {
  // N = 40 sessions of the baseline chain (free-running reference, coloured noise behind the
  // filter, declared, so the sandwich covariance). None may be flagged (0 of 240 runs were at
  // full size, README); one is allowed here. For each parameter the ratio of the scatter of the
  // estimates to the mean reported std has, for an honest std, a relative standard error of
  // 1/√(2(N − 1)) = 0.113: the tolerance is 3 of those, ±34 % (the ±20 % of issue 8 needs
  // N ≈ 110: benchmarks/carrier_accuracy_table --seeds, README). The mean error must be within
  // 3/√N = 0.47 of the reported std (unbiased), and no more than 15 % of the estimates beyond 2 of
  // their own std (4.6 % expected; 15 % is 3.2 binomial std above it at N = 40).
  constexpr int kSeeds = 40;
  const CarrierOptions options = Unit();
  const Eigen::Matrix<double, 10, 1> truth = Truth(options);
  std::vector<Eigen::Matrix<double, 10, 1>> estimates, stds;
  int flagged = 0;
  for (int i = 0; i < kSeeds; ++i) {
    const estimator::EstimateSummary s = estimator::EstimateMaximumLikelihood(
        Session(options, 1000u * (i + 1), /*undo=*/false), Production());
    ASSERT_TRUE(s.IsUsable()) << s.message;
    if (!s.diagnostics.Acceptable()) ++flagged;
    Eigen::Matrix<double, 10, 1> e, d;
    e << s.delta, s.xi;
    d << s.delta_std, s.xi_std;
    estimates.push_back(e);
    stds.push_back(d);
  }
  EXPECT_LE(flagged, 1);
  const double tolerance = 3.0 / std::sqrt(2.0 * (kSeeds - 1));
  for (int j = 0; j < 10; ++j) {
    double mean = 0.0, mean_std = 0.0;
    int beyond = 0;
    for (int i = 0; i < kSeeds; ++i) {
      mean += estimates[i][j] / kSeeds;
      mean_std += stds[i][j] / kSeeds;
      if (std::abs(estimates[i][j] - truth[j]) > 2 * stds[i][j]) ++beyond;
    }
    double scatter = 0.0;
    for (int i = 0; i < kSeeds; ++i) scatter += std::pow(estimates[i][j] - mean, 2);
    scatter = std::sqrt(scatter / (kSeeds - 1));
    RecordProperty("scatter_over_std_" + std::to_string(j), std::to_string(scatter / mean_std));
    EXPECT_NEAR(scatter / mean_std, 1.0, tolerance) << "parameter " << j;
    EXPECT_LT(std::abs(mean - truth[j]) / mean_std, 3.0 / std::sqrt(kSeeds)) << "parameter " << j;
    EXPECT_LE(beyond, 6) << "parameter " << j;
  }
}

}  // namespace
}  // namespace hrgbench::drivers::sim
