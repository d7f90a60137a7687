// Issue 28's chain as the bench runs it on the in-process simulated station: the production
// session's estimate → p → written over CAN → holds on the table in the operating mode → refined →
// written → verified; the table at zero at the end, whatever happened.
//
// The truth is set in the simulated unit (station config [simulated]); the "before" and "after"
// rate errors are measured from the electronics' angle output against the table's own measured
// rate, never from the code that computed p. Bounds: issue 28's (100× or the prediction), and the
// after residuals' χ² against the refined p's predicted covariance.

#include "hrgbench/bench/tuning/tune_unit.hpp"

#include <Eigen/Core>
#include <atomic>
#include <cmath>

#include "bench_test_support.hpp"
#include "hrgbench/config/site.hpp"

namespace hrgbench::testing {
namespace {

// A unit with everything free runs see: a damping split and its axis, a frequency split, the
// pick-off's gain and angle errors.
void UntunedUnit(bench::BenchConfigs& configs, double* earth_rate_rad_s) {
  configs.station.simulated.delta << -1e-3, 0.29, 3e-5, -2e-5, 2e-4, -1e-4;
  configs.station.simulated.xi << 0.01, 0.002, -0.003, 0.004;
  *earth_rate_rad_s = bench::EarthRateOnAxisRadS(configs.station.site);
}

// The station with that unit, no session run (the tests that need no estimate).
bool OpenUntunedStation(std::unique_ptr<app::Station>& station, double* earth_rate_rad_s) {
  return OpenShippedStation(
             "station-sim.toml", "sequence-production.toml", "",
             [&](bench::BenchConfigs& c) { UntunedUnit(c, earth_rate_rad_s); }, station)
      .has_value();
}

bench::TunePlan ShortPlan() {
  bench::TunePlan plan;
  plan.rates_rad_s = {0.3, -0.3};
  plan.verify_turns = 2.0;
  plan.refine_turns = 4.0;
  return plan;
}

TEST(TuneUnit, AnUntunedUnitIsTunedFromItsSessionAndVerifiedOnTheTable) {
  double earth = 0.0;
  BenchRun run = RunOnSimulatedStation("sequence-production.toml", "limits-example.toml",
                                       [&](bench::BenchConfigs& c) { UntunedUnit(c, &earth); });
  ASSERT_TRUE(run.result.estimate.has_value()) << run.result.reason;
  estimator::CompensationSet p;
  ASSERT_TRUE(estimator::CompensationFromEstimate(*run.result.estimate, &p));

  const bench::BenchHardware& hardware = run.station->hardware();
  bench::TunePlan plan = ShortPlan();
  plan.zero_rate_hold_s = 20.0;
  const bench::TuneResult tuned = bench::TuneUnit(hardware, hardware.units[0], p, plan, earth);
  ASSERT_TRUE(tuned.ok) << tuned.why;
  ASSERT_TRUE(tuned.held_before.has_value());
  // The factory block (the simulated electronics' default): design gain 0.3, decay 1e-3.
  EXPECT_EQ((*tuned.held_before)[1], 0.3);
  ASSERT_EQ(tuned.verified.size(), 2u);
  for (const bench::VerifiedRate& v : tuned.verified) {
    // The angle-dependent rate error before: the pick-off's −2Ω·ξ1, 2Ω·ξ4 and the damping split's
    // drift, ~6e-3 rad/s at 0.3 rad/s; after: 100× lower at least.
    EXPECT_GT(v.before_rms_rad_s, 1e-3) << "Ω = " << v.omega_rad_s;
    EXPECT_LT(v.after_rms_rad_s, v.before_rms_rad_s / 100.0) << "Ω = " << v.omega_rad_s;
    EXPECT_TRUE(v.met) << "Ω = " << v.omega_rad_s;
    RecordProperty(v.omega_rad_s > 0 ? "improvement_plus" : "improvement_minus",
                   std::to_string(v.before_rms_rad_s / v.after_rms_rad_s));
  }
  // Measured and predicted residuals agree: χ²(6) below its 0.999 quantile (22.46).
  EXPECT_TRUE(tuned.consistent) << "chi2 " << tuned.chi2 << " on " << tuned.chi2_dof;
  EXPECT_NEAR(tuned.chi2_limit, 22.458, 0.01);
  RecordProperty("chi2", std::to_string(tuned.chi2));

  // What the electronics hold is the refined p, bit for bit, and the table is at rest.
  EXPECT_EQ(tuned.block_at_end, "refined");
  EXPECT_FALSE(tuned.restored);
  auto held = hardware.units[0].operating->ReadParameters();
  ASSERT_TRUE(held.has_value()) << held.error().ToString();
  EXPECT_EQ(*held, bench::ToCompensationValues(tuned.refinement.refined));
  auto status = hardware.table->ReadStatus();
  ASSERT_TRUE(status.has_value());
  EXPECT_EQ(status->commanded_rate_rad_s, 0.0);
  // Every hold covered its turns with no sample lost.
  for (const auto* holds : {&tuned.before, &tuned.refine, &tuned.after}) {
    for (const bench::OperatingHold& hold : *holds) {
      EXPECT_EQ(hold.sequence_gaps, 0u);
      EXPECT_GT(hold.fit.angle_span_rad, 2.0 * std::numbers::pi * 1.9);
      EXPECT_EQ(hold.omega_source, "angle");
      EXPECT_NEAR(hold.omega_rad_s, hold.omega_set_rad_s + earth, 1e-6);
    }
  }
  // Over the rates, the refined gain leaves no scale-factor error the holds can see.
  ASSERT_TRUE(tuned.scale_factor.ok) << tuned.scale_factor.why;
  EXPECT_LT(std::abs(tuned.scale_factor.scale_factor_error),
            4.0 * tuned.scale_factor.scale_factor_error_std);
  EXPECT_LT(tuned.scale_factor.scale_factor_error_std, 1e-6);  // below 1 ppm
  // The zero-rate hold: the simulated electronics' angle output carries the pick-off's white noise
  // through the readout and no rate noise, so the Allan deviation of its rate falls as 1/τ (white
  // phase noise, NIST SP 1065 Table 2) at every τ the hold resolves well, and N is read at 1 s.
  ASSERT_TRUE(tuned.stability.has_value());
  const bench::ZeroRateStability& z = *tuned.stability;
  EXPECT_TRUE(z.arw_known);
  ASSERT_GE(z.allan.size(), 10u);
  for (std::size_t i = 1; i < z.allan.size(); ++i) {
    if (z.allan[i].tau_s > 0.3) break;  // the intervals widen: 1/τ within them, not within 10 %
    const double ratio = z.allan[i].deviation / z.allan[i - 1].deviation;
    EXPECT_NEAR(ratio * z.allan[i].tau_s / z.allan[i - 1].tau_s, 1.0, 0.1)
        << "τ " << z.allan[i].tau_s;
  }
  EXPECT_FALSE(z.bias_instability_reached);  // σ still falls at the longest τ of 20 s
  const nlohmann::json record = bench::TuneResultJson(tuned);
  EXPECT_EQ(record.at("block_at_end"), "refined");
  EXPECT_EQ(record.at("holds").at("after").size(), 2u);
  EXPECT_EQ(record.at("refined").at("covariance").size(), 11u);
}

// What free runs cannot see (issue 28 §4), at the bench: forcers with gain, angle and frame errors
// (station [simulated] forcer_errors). Read with p from the free runs, the refine holds show the
// drift and bias the forcers add through the energy loop's effort g = −δ1, as derived in
// docs/estimator/operating-mode.md (terms 4 and 5: Δδ3 = g·β1, Δδ4 = g·β4, a bias −g·b/(2δ2);
// c = −Δδ4/(2δ2), s = Δδ3/(2δ2)), and the refined p removes them.
TEST(TuneUnit, TheRefinementRemovesWhatTheForcersAddAndFreeRunsCannotSee) {
  const double beta1 = 5e-3, beta4 = -4e-3, b = 3e-3, delta1 = -1e-3, delta2 = 0.29;
  double earth = 0.0;
  BenchRun run = RunOnSimulatedStation(
      "sequence-production.toml", "limits-example.toml", [&](bench::BenchConfigs& c) {
        UntunedUnit(c, &earth);
        c.station.simulated.forcer_errors = {beta1, 0.0, 0.0, beta4, b};
      });
  ASSERT_TRUE(run.result.estimate.has_value()) << run.result.reason;
  estimator::CompensationSet p;
  ASSERT_TRUE(estimator::CompensationFromEstimate(*run.result.estimate, &p));
  const bench::BenchHardware& hardware = run.station->hardware();
  const bench::TuneResult tuned =
      bench::TuneUnit(hardware, hardware.units[0], p, ShortPlan(), earth);
  ASSERT_TRUE(tuned.ok) << tuned.why;
  ASSERT_EQ(tuned.refine.size(), 2u);
  const double g = -delta1;
  const double c = -g * beta4 / (2.0 * delta2), s = g * beta1 / (2.0 * delta2);
  const double bias = -g * b / (2.0 * delta2);
  for (std::size_t i = 0; i < 2; ++i) {
    const analysis::RateErrorHarmonics& f = tuned.refine[i].fit;
    // p's own errors (from the free runs) add their predicted spread; 5 σ of both.
    const Eigen::Matrix3d predicted =
        estimator::PredictedRateErrorCovariance(p, tuned.refine[i].omega_rad_s);
    EXPECT_NEAR(f.cos_rad_s[0], c,
                5.0 * std::sqrt(f.cos_std_rad_s[0] * f.cos_std_rad_s[0] + predicted(1, 1)))
        << "Ω " << tuned.refine[i].omega_rad_s;
    EXPECT_NEAR(f.sin_rad_s[0], s,
                5.0 * std::sqrt(f.sin_std_rad_s[0] * f.sin_std_rad_s[0] + predicted(2, 2)));
    EXPECT_NEAR(f.bias_rad_s, bias,
                5.0 * std::sqrt(f.bias_std_rad_s * f.bias_std_rad_s + predicted(0, 0)));
    // Removed by the refinement: the after hold at the same rate is at its noise.
    EXPECT_LT(tuned.after[i].fit.angle_dependent_rms_rad_s,
              tuned.refine[i].fit.angle_dependent_rms_rad_s / 3.0);
    EXPECT_LT(std::abs(tuned.after[i].fit.bias_rad_s), std::abs(bias) / 3.0);
  }
  EXPECT_TRUE(tuned.consistent) << "chi2 " << tuned.chi2 << " on " << tuned.chi2_dof;
}

// The same chain at carrier level (station-sim-carrier.toml: the resonator at its 5 kHz carrier,
// the pick-off channels with their errors and noise, the demodulating electronics; the forcers
// driven at the carrier through their own errors, in the electrode frame). The criterion:
// the angle-dependent rate error falls by at least 100×, and the after holds agree with the refined
// p's prediction (χ² below its 0.999 quantile). The laws themselves are
// carrier_operating_mode_test's.
TEST(TuneUnit, ACarrierUnitWithForcerErrorsIsTunedAtTheBench) {
  double earth = 0.0;
  BenchRun run = RunOnSimulatedStation(
      "sequence-production.toml", "limits-example.toml",
      [&](bench::BenchConfigs& c) {
        c.station.simulated.forcer_errors = {3e-3, 1e-3, -1e-3, -2e-3, 2e-3};
        earth = bench::EarthRateOnAxisRadS(c.station.site);
      },
      {}, {}, "station-sim-carrier.toml");
  ASSERT_EQ(run.result.outcome, bench::OutcomeKind::kPass) << run.result.reason;
  ASSERT_TRUE(run.result.estimate.has_value()) << run.result.reason;
  estimator::CompensationSet p;
  ASSERT_TRUE(estimator::CompensationFromEstimate(*run.result.estimate, &p));
  const bench::BenchHardware& hardware = run.station->hardware();
  const bench::TuneResult tuned =
      bench::TuneUnit(hardware, hardware.units[0], p, ShortPlan(), earth);
  ASSERT_TRUE(tuned.ok) << tuned.why;
  ASSERT_EQ(tuned.verified.size(), 2u);
  for (const bench::VerifiedRate& v : tuned.verified) {
    EXPECT_GT(v.before_rms_rad_s, 1e-3) << "Ω = " << v.omega_rad_s;  // ξ1 = 0.01: 2Ω·ξ1
    EXPECT_LT(v.after_rms_rad_s, v.before_rms_rad_s / 100.0) << "Ω = " << v.omega_rad_s;
    RecordProperty(v.omega_rad_s > 0 ? "improvement_plus" : "improvement_minus",
                   std::to_string(v.before_rms_rad_s / v.after_rms_rad_s));
  }
  EXPECT_TRUE(tuned.consistent) << "chi2 " << tuned.chi2 << " on " << tuned.chi2_dof;
  RecordProperty("chi2", std::to_string(tuned.chi2));
  EXPECT_EQ(tuned.block_at_end, "refined");
  for (const bench::OperatingHold& hold : tuned.after) {
    EXPECT_EQ(hold.sequence_gaps, 0u);
    // The electronics' loops held the wave through the hold (their reports over CAN, every 10th
    // sample): on average the quadrature nulled and the energy at its set point (each report is one
    // noisy sample: their RMS is the pick-off noise's, ~2e-4 relative; 10 RMS/√reports allows for
    // the loops' correlation over ~5 reports), and the amplitude loop's mean effort is the unit's
    // decay rate, 1/τ = 1e-3 1/s: its proportional part moves g by kp·e ≈ 4e-3 1/s per sample on
    // this noise, so over ~3500 reports the mean is 1e-3 within ±1.5e-4 (1σ).
    EXPECT_GT(hold.loops.reports, hold.samples / 10 - 2);
    EXPECT_EQ(hold.loops.incomplete, 0u);
    const double reports = static_cast<double>(hold.loops.reports);
    EXPECT_LT(std::abs(hold.loops.Mean(1)), 10.0 * hold.loops.Rms(1) / std::sqrt(reports));
    EXPECT_LT(hold.loops.Rms(1), 1e-3);
    EXPECT_LT(std::abs(hold.loops.Mean(0)), 10.0 * hold.loops.Rms(0) / std::sqrt(reports));
    EXPECT_NEAR(hold.loops.Mean(2), 1e-3, 4e-4);
  }
  auto status = hardware.table->ReadStatus();
  ASSERT_TRUE(status.has_value());
  EXPECT_EQ(status->commanded_rate_rad_s, 0.0);
}

TEST(TuneUnit, AStopRequestEndsItWithTheTableCommandedToZeroAndTheBlockNamed) {
  double earth = 0.0;
  std::unique_ptr<app::Station> station;
  ASSERT_TRUE(OpenUntunedStation(station, &earth));
  const bench::BenchHardware& hardware = station->hardware();
  estimator::CompensationSet p = estimator::IdentityCompensation(0.29, -1e-3);
  std::atomic<int> stop{0};
  int logged = 0;
  // Stopped once p is written: during the first refinement hold.
  const bench::TuneResult result = bench::TuneUnit(
      hardware, hardware.units[0], p, ShortPlan(), earth, &stop, [&](std::string_view line) {
        ++logged;
        if (line.find("written") != std::string_view::npos) stop = 1;
      });
  EXPECT_FALSE(result.ok);
  EXPECT_NE(result.why.find("stopped"), std::string::npos) << result.why;
  EXPECT_EQ(result.block_at_end, "from the estimate");
  EXPECT_GT(logged, 2);
  auto status = hardware.table->ReadStatus();
  ASSERT_TRUE(status.has_value());
  EXPECT_EQ(status->commanded_rate_rad_s, 0.0);
  EXPECT_EQ(hardware.units[0].gyro->State(), hw::GyroMode::kStopped);
}

TEST(TuneUnit, APlanWithoutBothSignsIsRefusedBeforeAnythingMoves) {
  double earth = 0.0;
  std::unique_ptr<app::Station> station;
  ASSERT_TRUE(OpenUntunedStation(station, &earth));
  const bench::BenchHardware& hardware = station->hardware();
  bench::TunePlan plan = ShortPlan();
  plan.rates_rad_s = {0.3, 1.0};
  const bench::TuneResult result = bench::TuneUnit(
      hardware, hardware.units[0], estimator::IdentityCompensation(0.3, -1e-3), plan, earth);
  EXPECT_FALSE(result.ok);
  EXPECT_NE(result.why.find("both signs"), std::string::npos) << result.why;
  EXPECT_FALSE(result.first_write.has_value());
  EXPECT_EQ(hardware.units[0].gyro->State(), hw::GyroMode::kIdle);
}

}  // namespace
}  // namespace hrgbench::testing
