// Carrier-level sessions through the session format and the bench's preparation of a record
// (bench/recorded_runs.hpp), against the simulator's physics:
//  - the I/Q convention: electronics that demodulate with y_Q = +2·LPF[s·sin ψ] ("plus-sine"),
//    declared so, estimate the truth; declared as the model's "minus-sine", the fit is named;
//  - the release transient: the declared output filter's settling after release is not fitted,
//    so the shipped carrier station's runs lose no sample as an "outlier", while a real spike
//    later in a run is still removed and said.
// Provenance: drivers/sim's CarrierSimulation (the unit of bench_configs/station-sim-carrier.toml
// as carrier_estimate_test.cpp has it: white converter noise 1.1e-3 → σ_y ≈ 1e-4 behind the 4th-
// order 200 Hz filter), the production design's six rates shortened to 5 s runs at 1 kHz, seeds
// in each test.

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "hrgbench/analysis/estimate_method.hpp"
#include "hrgbench/analysis/output_filter.hpp"
#include "hrgbench/analysis/recorded_estimate.hpp"
#include "hrgbench/analysis/recorded_runs.hpp"
#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_record.hpp"
#include "sim/butterworth_low_pass.hpp"
#include "sim/carrier_simulation.hpp"

namespace hrgbench::drivers::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRunS = 5.0;
constexpr double kRateHz = 1000.0;

CarrierOptions Unit(estimator::IqConvention convention = estimator::IqConvention::kMinusSine) {
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
  o.electronics.iq_convention = convention;
  return o;
}

// The chain's filter as a station declares it ([gyro] output_filter, bench_configs/README.md).
bench::OutputFilter ChainFilter() {
  const CarrierElectronicsOptions electronics;
  return {bench::OutputFilterKind::kButterworth, electronics.filter_order,
          electronics.filter_cutoff_hz};
}

class ScratchDir {
 public:
  ScratchDir() {
    static std::atomic<int> counter{0};
    path_ = std::filesystem::temp_directory_path() /
            ("hrgbench_carrier_session_" + std::to_string(::getpid()) + "_" +
             std::to_string(counter.fetch_add(1)));
    std::filesystem::remove_all(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

struct Spike {
  int run_id = 0;  // 0: none
  double t_s = 0.0;
  double size = 0.0;  // added to y1
};

// Simulates the production's six runs and records them as the bench does (session.json with
// electronics.output_filter and the declared iq_convention, one CSV per run, t_s since release),
// then reads the session back.
session::Session RecordedSession(const ScratchDir& dir, const CarrierOptions& options,
                                 std::uint64_t seed, estimator::IqConvention declared,
                                 const Spike& spike = {}) {
  const double omegas[6] = {0.1, -0.1, 0.3, -0.3, 1.0, -1.0};
  const double bs[6] = {0.0, 0.1, 0.2, 0.0, 0.1, 0.2};
  CarrierSimulation sim(options);
  session::Session s;
  s.serial = "SIM-CARRIER";
  s.sample_rate_hz = kRateHz;
  s.iq_convention = declared;
  s.document = {{"electronics", {{"output_filter", bench::OutputFilterJson(ChainFilter())}}},
                {"runs", nlohmann::json::array()}};
  const int n = static_cast<int>(std::lround(kRunS * kRateHz));
  for (int r = 0; r < 6; ++r) {
    sim.Release({{1.0, bs[r], r * kPi / 12.0, 0.0}, omegas[r], kRateHz, seed + r, 25.0, 0.0});
    session::RunSamples samples;
    samples.y.resize(4, n);
    for (int k = 0; k < n; ++k) {
      samples.t_s.push_back(k / kRateHz);
      samples.y.col(k) = sim.Next(omegas[r]);
    }
    if (spike.run_id == r + 1) samples.y(0, std::lround(spike.t_s * kRateHz)) += spike.size;
    const std::string file = "runs/run-00" + std::to_string(r + 1) + ".csv";
    EXPECT_TRUE(session::WriteRunCsv(dir.path() / file, samples));
    s.runs.push_back({r + 1, file, omegas[r], "complete"});
    // The plan as the bench records it: the orbit commanded at release (the model's convention).
    s.document["runs"].push_back(
        {{"id", r + 1}, {"plan", {{"a", 1.0}, {"b", bs[r]}, {"theta_rad", r * kPi / 12.0}}}});
  }
  EXPECT_TRUE(session::WriteSessionJson(dir.path(), s));
  auto read = session::ReadSession(dir.path());
  EXPECT_TRUE(read) << read.error().ToString();
  return read ? *read : session::Session{};
}

// The same session.json typed by the record's one reader, as the sequencer reads it back.
session::SessionRecord RecordOf(const session::Session& recorded) {
  auto record = session::ReadSessionRecord(recorded.document, "session.json");
  EXPECT_TRUE(record) << record.error().ToString();
  return record ? *std::move(record) : session::SessionRecord{};
}

// The estimate of record, as the sequencer makes it.
bench::RecordedEstimate EstimateOf(const session::Session& recorded) {
  return bench::EstimateRecordedSession(recorded, RecordOf(recorded), {});
}

Eigen::Matrix<double, 10, 1> Truth(const CarrierOptions& options) {
  const CarrierSimulation sim(options);
  Eigen::Matrix<double, 10, 1> truth;
  truth << sim.delta(), sim.xi();
  return truth;
}

bool AnyContains(const std::vector<std::string>& lines, const std::string& what) {
  for (const std::string& line : lines)
    if (line.find(what) != std::string::npos) return true;
  return false;
}

// ---- The I/Q convention -------------------------------------------------------------------------

TEST(CarrierSessionTest, PlusSineElectronicsOutputTheConjugateOfTheModelsChannels) {
  // Same wave, same converter noise: the in-phase channels equal, the quadrature ones negated
  // (before the wire's quantisation, whose rounding is not symmetric to the last LSB).
  CarrierOptions minus = Unit(), plus = Unit(estimator::IqConvention::kPlusSine);
  minus.electronics.quantise = plus.electronics.quantise = false;
  CarrierSimulation a(minus), b(plus);
  a.Release({{1.0, 0.1, 0.3, 0.0}, 0.3, kRateHz, 5, 25.0, 0.0});
  b.Release({{1.0, 0.1, 0.3, 0.0}, 0.3, kRateHz, 5, 25.0, 0.0});
  for (int k = 0; k < 200; ++k) {
    const estimator::Observation ya = a.Next(0.3), yb = b.Next(0.3);
    EXPECT_EQ(yb[0], ya[0]);
    EXPECT_EQ(yb[1], -ya[1]);
    EXPECT_EQ(yb[2], ya[2]);
    EXPECT_EQ(yb[3], -ya[3]);
  }
}

TEST(CarrierSessionTest, PlusSineSessionDeclaredSoEstimatesTheTruth) {
  // Conjugated back by the reader's declared convention, every parameter within 4 of its reported
  // std of the simulator's truth (6e-5 per parameter by chance for an honest std), and the fit is
  // within its model.
  const CarrierOptions options = Unit(estimator::IqConvention::kPlusSine);
  const ScratchDir dir;
  const session::Session recorded =
      RecordedSession(dir, options, 31, estimator::IqConvention::kPlusSine);
  EXPECT_TRUE(AnyContains(recorded.notes, "'plus-sine'"));
  const bench::RecordedEstimate e = EstimateOf(recorded);
  const estimator::EstimateSummary& s = e.method.summary;
  ASSERT_TRUE(s.IsUsable()) << s.message;
  EXPECT_TRUE(s.diagnostics.Acceptable())
      << (s.diagnostics.problems.empty() ? "" : s.diagnostics.problems.front());
  const Eigen::Matrix<double, 10, 1> truth = Truth(options);
  for (int j = 0; j < 6; ++j) EXPECT_LT(std::abs(s.delta[j] - truth[j]), 4 * s.delta_std[j]) << j;
  for (int j = 0; j < 4; ++j) EXPECT_LT(std::abs(s.xi[j] - truth[6 + j]), 4 * s.xi_std[j]) << j;
  EXPECT_EQ(e.report["preparation"]["iq_convention"], "plus-sine");
}

TEST(CarrierSessionTest, PlusSineSessionDeclaredAsTheModelsIsNamed) {
  // The same data declared "minus-sine". Conjugation is an exact symmetry of the free-run model
  // (estimator/iq_convention.hpp): the fit is as good as ever, δ2 (and δ1, δ3, δ4, ξ1, ξ4) as
  // true as declared, and δ5, δ6, ξ2, ξ3 come out negated, each within 4 std. Only a sign fixed
  // outside the free run tells: the quadrature commanded at release, and it is named.
  const CarrierOptions options = Unit(estimator::IqConvention::kPlusSine);
  const ScratchDir dir;
  const session::Session recorded =
      RecordedSession(dir, options, 31, estimator::IqConvention::kMinusSine);
  const bench::RecordedEstimate e = EstimateOf(recorded);
  const estimator::EstimateSummary& s = e.method.summary;
  ASSERT_TRUE(s.IsUsable()) << s.message;
  const Eigen::Matrix<double, 10, 1> truth = Truth(options);
  for (int j : {0, 1, 2, 3}) EXPECT_LT(std::abs(s.delta[j] - truth[j]), 4 * s.delta_std[j]) << j;
  for (int j : {4, 5}) EXPECT_LT(std::abs(s.delta[j] + truth[j]), 4 * s.delta_std[j]) << j;
  for (int j : {0, 3}) EXPECT_LT(std::abs(s.xi[j] - truth[6 + j]), 4 * s.xi_std[j]) << j;
  for (int j : {1, 2}) EXPECT_LT(std::abs(s.xi[j] + truth[6 + j]), 4 * s.xi_std[j]) << j;
  for (const estimator::RunFitDiagnostics& run : s.diagnostics.runs)
    EXPECT_LT(run.residual_ratio, run.residual_ratio_threshold) << "run " << run.run_id;
  ASSERT_FALSE(s.diagnostics.Acceptable());
  EXPECT_EQ(s.diagnostics.problems.size(), 1u);
  EXPECT_TRUE(AnyContains(s.diagnostics.problems, "electronics.iq_convention"));
  EXPECT_TRUE(AnyContains(s.warnings, "opposite sign of the commanded one"));
  EXPECT_FALSE(e.report["fit"]["acceptable"].get<bool>());
  // Declared right (the previous test), the same check is silent: the check is the declaration's.
  EXPECT_FALSE(bench::IqConventionContradiction(
      RecordOf(recorded),
      EstimateOf(RecordedSession(dir, options, 31, estimator::IqConvention::kPlusSine))
          .method.summary));
}

// ---- The release transient ----------------------------------------------------------------------

TEST(CarrierSessionTest, ReleaseSettlingBoundsTheChainFiltersStepResponse) {
  // Independent of the bound's derivation: the simulator's own filter (bilinear biquads at the
  // converter rate, 100 kHz) stepped from rest. Its output stays within 1e-6 of the step from the
  // settling time on, and the bound is not wasteful: the last excursion beyond 1e-6 is at least
  // 0.7 of it. Also for the 8th order at 100 Hz.
  for (const auto& [order, cutoff_hz] : {std::pair{4, 200.0}, std::pair{8, 100.0}}) {
    const double settle_s =
        bench::ReleaseSettlingS({bench::OutputFilterKind::kButterworth, order, cutoff_hz});
    ButterworthLowPass filter(order, cutoff_hz, 100000.0);
    filter.SetSteadyState(Eigen::Array4d::Zero());
    double last_excursion_s = 0.0;
    for (int k = 0; k < 20000; ++k) {  // 0.2 s
      const double y = filter.Filter(Eigen::Array4d::Ones())[0];
      if (std::abs(y - 1.0) > bench::kReleaseSettlingFraction) last_excursion_s = (k + 1) / 1e5;
    }
    EXPECT_LE(last_excursion_s, settle_s) << order << " " << cutoff_hz;
    EXPECT_GE(last_excursion_s, 0.7 * settle_s) << order << " " << cutoff_hz;
  }
  EXPECT_EQ(bench::ReleaseSettlingS({}), 0.0);  // no filter declared: nothing skipped
}

TEST(CarrierSessionTest, ReleaseTransientIsSkippedNotCountedAsOutliers) {
  // The shipped carrier station's finding: every run lost samples right after release as 50–70 σ
  // "outliers". Prepared as the bench prepares a record, no run loses any, and the record says
  // what was skipped; fitted from release (the control), every run loses some, all of them
  // inside the settling time.
  const CarrierOptions options = Unit();
  const ScratchDir dir;
  const session::Session recorded =
      RecordedSession(dir, options, 41, estimator::IqConvention::kMinusSine);
  const bench::RecordedEstimate e = EstimateOf(recorded);
  const estimator::EstimateSummary& s = e.method.summary;
  ASSERT_TRUE(s.IsUsable()) << s.message;
  const double settle_s = bench::ReleaseSettlingS(ChainFilter());
  ASSERT_EQ(s.diagnostics.runs.size(), 6u);
  for (const estimator::RunFitDiagnostics& run : s.diagnostics.runs)
    EXPECT_EQ(run.outliers_removed, 0u) << "run " << run.run_id;
  EXPECT_TRUE(s.diagnostics.Acceptable());
  const nlohmann::json& settling = e.report["preparation"]["release_settling"];
  EXPECT_EQ(settling["settle_s"].get<double>(), settle_s);
  EXPECT_EQ(settling["output_filter"], "4th-order Butterworth, 200 Hz");
  ASSERT_EQ(settling["runs"].size(), 6u);
  for (const nlohmann::json& run : settling["runs"]) {
    EXPECT_EQ(run["samples_skipped"].get<std::size_t>(),
              static_cast<std::size_t>(std::ceil(settle_s * kRateHz)));
    EXPECT_GE(run["first_fitted_t_s"].get<double>(), settle_s);
  }

  // The control: the same record fitted from release.
  bench::MethodRequest request;
  request.noise_shape =
      *bench::RecordedNoiseShape(RecordOf(recorded).electronics, recorded.sample_rate_hz);
  const estimator::EstimateSummary control =
      bench::RunMethod(session::ToRunData(recorded), request).summary;
  ASSERT_TRUE(control.IsUsable()) << control.message;
  for (const estimator::RunFitDiagnostics& run : control.diagnostics.runs) {
    EXPECT_GT(run.outliers_removed, 0u) << "run " << run.run_id;
    EXPECT_LE(run.outliers_removed, static_cast<std::size_t>(settle_s * kRateHz));
    EXPECT_GT(run.largest_outlier_in_sigma, 20.0) << "run " << run.run_id;
  }
}

TEST(CarrierSessionTest, RealSpikeLaterInARunIsStillRemovedAndSaid) {
  // A 5e-3 spike (about 50 σ_y) on y1 of run 3 at t = 2.5 s: removed, counted and said; no
  // other run loses a sample.
  const ScratchDir dir;
  const session::Session recorded =
      RecordedSession(dir, Unit(), 41, estimator::IqConvention::kMinusSine, {3, 2.5, 5e-3});
  const bench::RecordedEstimate e = EstimateOf(recorded);
  const estimator::EstimateSummary& s = e.method.summary;
  ASSERT_TRUE(s.IsUsable()) << s.message;
  for (const estimator::RunFitDiagnostics& run : s.diagnostics.runs) {
    EXPECT_EQ(run.outliers_removed, run.run_id == 3 ? 1u : 0u) << "run " << run.run_id;
    if (run.run_id == 3) {
      EXPECT_GT(run.largest_outlier_in_sigma, 20.0);
    }
  }
  EXPECT_TRUE(AnyContains(s.warnings, "run 3: 1 samples removed as outliers"));
}

}  // namespace
}  // namespace hrgbench::drivers::sim
