// The engineering quantities (engineering_quantities.hpp): the maps against the physical
// parameters they come from and against the real 4×4 system's eigenvalues (Eigen's general
// eigensolver, not the complex closed form the code uses), their delta-method standard errors
// against a Monte Carlo scatter, and the undetermined axis. Their physics (a simulated oscillator
// beats at Δf, decays at τ1 and τ2, precesses at −kΩ) is tests/unit/sim/engineering_physics_test.

#include "hrgbench/estimator/engineering_quantities.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "../../support/out_of_model.hpp"
#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/model.hpp"
#include "hrgbench/estimator/physical_parameters.hpp"
#include "hrgbench/estimator/pickoff_frame.hpp"

namespace hrgbench::estimator {
namespace {

using Q = EngineeringQuantity;
constexpr double kPi = std::numbers::pi;
constexpr double kF0 = 5000.0;

double At(const std::array<double, kEngineeringQuantityCount>& v, Q q) {
  return v[static_cast<std::size_t>(q)];
}

TEST(EngineeringQuantitiesTest, NamesAreUniqueAndCarryTheirUnits) {
  for (std::size_t i = 0; i < kEngineeringQuantityCount; ++i) {
    for (std::size_t j = i + 1; j < kEngineeringQuantityCount; ++j)
      EXPECT_NE(kEngineeringQuantities[i].name, kEngineeringQuantities[j].name);
  }
  EXPECT_EQ(Info(Q::kDecayTime).name, "tau_s");
  EXPECT_EQ(Info(Q::kQualityFactor).name, "q_factor");
  EXPECT_EQ(Info(Q::kFrequencySplit).name, "frequency_split_mhz");
  EXPECT_EQ(Info(Q::kFrequencySplit).unit, "mHz");
}

// The resonator and the pick-off set in physical terms come back in the field's units: τ, Q =
// π·f0·τ, Δf in mHz, the axes on the shell (half the model's angle), k, and the pick-off errors.
TEST(EngineeringQuantitiesTest, ValuesAreThePhysicalParametersInTheFieldsUnits) {
  ResonatorParameters r;
  r.frequency_hz = kF0;
  r.decay_time_s = 800.0;
  r.damping_anisotropy_per_s = 4e-5;
  r.damping_axis_rad = 0.6;  // model (electrical) angle: 0.3 rad = 17.19° on the shell
  r.frequency_split_hz = 0.02;
  r.frequency_axis_rad = -1.0;  // −28.65° on the shell
  r.angular_gain = 0.29;
  PickoffParameters p;
  p.gain_ratio = 1.012;
  p.phase_mismatch_rad = 0.004;
  p.cross_talk = 0.003;
  p.electrode_angle_error_rad = 0.01;
  // What the slow model's fit sees of this unit: δ in its frame, ξ with the split's mixing.
  const SlowModelTruth seen = SlowModelSeenOnUnit(r, PhysicalPickoffGain(p));
  const auto v = EngineeringValues(seen.delta, seen.xi, kF0);
  EXPECT_DOUBLE_EQ(At(v, Q::kResonantFrequency), kF0);
  EXPECT_NEAR(At(v, Q::kDecayTime), 800.0, 1e-9);
  EXPECT_NEAR(At(v, Q::kQualityFactor), kPi * 5000.0 * 800.0, 1e-3);  // 1.2566e7
  EXPECT_NEAR(At(v, Q::kDampingSplit), 4e-5, 1e-12);
  EXPECT_NEAR(At(v, Q::kDampingAxis), 0.3 * 180.0 / kPi, 1e-9);
  EXPECT_NEAR(At(v, Q::kFrequencySplit), 20.0, 1e-9);
  EXPECT_NEAR(At(v, Q::kFrequencyAxis), -0.5 * 180.0 / kPi, 1e-9);
  EXPECT_DOUBLE_EQ(At(v, Q::kAngularGain), 0.29);
  EXPECT_NEAR(At(v, Q::kPickoffGainMismatch), 1.2, 1e-9);
  EXPECT_NEAR(At(v, Q::kPickoffPhaseMismatch), 0.004 * 180.0 / kPi, 1e-9);
  EXPECT_NEAR(At(v, Q::kPickoffCrossTalk), 0.3, 1e-10);
  EXPECT_NEAR(At(v, Q::kElectrodeAngle), 0.005 * 180.0 / kPi, 1e-9);
}

// τ1, τ2 are the decay times of the free modes: the real parts of the eigenvalues of the real 4×4
// system matrix A(0, δ), computed here by Eigen's general eigensolver. When the damping and the
// frequency axes differ (by up to 45° on the shell, the model's π/2) the modes mix both, so their
// split is below Δ(1/τ).
TEST(EngineeringQuantitiesTest, ModeDecayTimesAreTheSystemsEigenvalues) {
  for (double axis_gap_rad : {0.0, 0.5, kPi / 4, kPi / 3, kPi / 2}) {
    ResonatorParameters r;
    r.frequency_hz = kF0;
    r.decay_time_s = 500.0;
    r.damping_anisotropy_per_s = 3e-4;
    r.damping_axis_rad = 0.2;
    r.frequency_split_hz = 2e-5;  // π·Δf = 6.3e-5 rad/s, comparable with Δ(1/τ)/2 = 1.5e-4
    r.frequency_axis_rad = 0.2 + axis_gap_rad;
    const Delta delta = DeltaFromResonator(r);
    Eigen::EigenSolver<Eigen::Matrix4d> solver(SystemMatrix(0.0, delta));
    std::vector<double> rates;
    for (int i = 0; i < 4; ++i) rates.push_back(-solver.eigenvalues()[i].real());
    std::sort(rates.begin(), rates.end());
    const auto v = EngineeringValues(delta, Xi::Zero(), kF0);
    SCOPED_TRACE(axis_gap_rad);
    EXPECT_NEAR(1.0 / At(v, Q::kSlowModeDecayTime), rates[0], 1e-12);
    EXPECT_NEAR(1.0 / At(v, Q::kFastModeDecayTime), rates[3], 1e-12);
    EXPECT_GE(At(v, Q::kSlowModeDecayTime), At(v, Q::kDecayTime));
    EXPECT_LE(1.0 / At(v, Q::kFastModeDecayTime) - 1.0 / At(v, Q::kSlowModeDecayTime),
              r.damping_anisotropy_per_s + 1e-15);
  }
}

// The production design, shortened (10 s at 100 Hz a run), and a resonator whose splits are well
// above the noise so every axis is determined and the maps are linear over the scatter.
std::vector<RunData> Session(const SimulationOptions& truth, std::uint64_t seed) {
  SimulationOptions o = truth;
  o.sigma = 1e-4;
  o.seed = seed;
  return SimulateRuns(testing::ProductionPlans(10.0, 100.0), o);
}

SimulationOptions AnisotropicTruth() {
  SimulationOptions truth;
  truth.delta << -1e-3, 0.3, 2e-5, -1e-5, 3e-4, -2e-4;
  truth.xi << 0.01, -0.003, 0.002, 0.004;
  return truth;
}

// The delta method's standard errors against the scatter over 200 simulated sessions, within
// ±20 % (the tolerance; the sample std of 200 draws has a relative standard error of 5 %,
// so this is 4 of them). The mean of each quantity is also within 4 standard errors of the truth's.
TEST(EngineeringQuantitiesTest, DeltaMethodStdMatchesMonteCarloScatter) {
  const SimulationOptions truth = AnisotropicTruth();
  const auto true_values = EngineeringValues(truth.delta, truth.xi, kF0);
  constexpr int kSeeds = 200;
  std::array<std::vector<double>, kEngineeringQuantityCount> values, stds;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const EstimateSummary s = EstimateMaximumLikelihood(Session(truth, 7000 + seed));
    ASSERT_TRUE(s.IsUsable()) << s.Report();
    const EngineeringQuantities e = ComputeEngineeringQuantities(s, kF0);
    for (std::size_t k = 1; k < kEngineeringQuantityCount; ++k) {  // f0 is given, not estimated
      ASSERT_TRUE(e.values[k].determined)
          << kEngineeringQuantities[k].name << " seed " << seed << ": " << e.values[k].note;
      values[k].push_back(e.values[k].value);
      // The fit's statistical part: what scatters over seeds (the budget's systematic parts are
      // the same in every session).
      stds[k].push_back(e.values[k].statistical_std);
    }
  }
  for (std::size_t k = 1; k < kEngineeringQuantityCount; ++k) {
    SCOPED_TRACE(std::string(kEngineeringQuantities[k].name));
    double mean = 0.0;
    for (double v : values[k]) mean += v / kSeeds;
    double scatter = 0.0, reported = 0.0;
    for (int i = 0; i < kSeeds; ++i) {
      scatter += (values[k][i] - mean) * (values[k][i] - mean) / (kSeeds - 1);
      reported += stds[k][i] * stds[k][i] / kSeeds;
    }
    scatter = std::sqrt(scatter);
    reported = std::sqrt(reported);
    EXPECT_GT(reported, 0.8 * scatter);
    EXPECT_LT(reported, 1.2 * scatter);
    EXPECT_LT(std::abs(mean - true_values[k]), 4.0 * scatter / std::sqrt(kSeeds));
  }
}

// No frequency split: its axis is noise and is reported undetermined (the test's level is 3σ, so
// about 0.3 % of sessions still call it determined); with the split above, never.
TEST(EngineeringQuantitiesTest, TheAxisOfAnInsignificantSplitIsUndetermined) {
  SimulationOptions isotropic = AnisotropicTruth();
  isotropic.delta[kFrequencyAnisotropyCos] = 0.0;
  isotropic.delta[kFrequencyAnisotropySin] = 0.0;
  int undetermined = 0;
  constexpr int kSeeds = 60;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const EstimateSummary s = EstimateMaximumLikelihood(Session(isotropic, 9000 + seed));
    ASSERT_TRUE(s.IsUsable());
    const EngineeringQuantities e = ComputeEngineeringQuantities(s, kF0);
    const EngineeringValue& axis = e[Q::kFrequencyAxis];
    if (!axis.determined) {
      ++undetermined;
      EXPECT_TRUE(std::isnan(axis.value));
      EXPECT_NE(axis.note.find("not significantly different from zero"), std::string::npos);
      EXPECT_TRUE(e[Q::kFrequencySplit].determined);  // the split itself is still a measurement
    }
    EXPECT_TRUE(e[Q::kDampingAxis].determined) << e[Q::kDampingAxis].note;
  }
  EXPECT_GE(undetermined, kSeeds - 2);
}

// A held parameter determines nothing that depends on it; an unknown f0 leaves Q unknown.
TEST(EngineeringQuantitiesTest, HeldParametersAndUnknownFrequencyAreNotDetermined) {
  MlOptions options;
  options.xi_estimated = {true, true, false, true};  // cross-talk held at 0
  const SimulationOptions truth = AnisotropicTruth();
  SimulationOptions no_cross_talk = truth;
  no_cross_talk.xi[kCrossTalk] = 0.0;
  const EstimateSummary s = EstimateMaximumLikelihood(Session(no_cross_talk, 5), options);
  ASSERT_TRUE(s.IsUsable());
  const EngineeringQuantities e = ComputeEngineeringQuantities(s, std::nan(""));
  EXPECT_FALSE(e[Q::kPickoffCrossTalk].determined);
  EXPECT_EQ(e[Q::kPickoffCrossTalk].note, "xi3 was held, not estimated");
  // ξ3 held at 0 is a physical κ of second order in the other errors (pickoff_frame.hpp).
  EXPECT_NEAR(e[Q::kPickoffCrossTalk].value, 0.0, 1e-3);
  EXPECT_TRUE(std::isnan(e[Q::kPickoffCrossTalk].std));
  EXPECT_TRUE(e[Q::kPickoffGainMismatch].determined);
  EXPECT_FALSE(e[Q::kQualityFactor].determined);
  EXPECT_EQ(e[Q::kQualityFactor].note, "the resonant frequency is unknown");
  EXPECT_TRUE(e[Q::kDecayTime].determined);

  EstimateSummary not_run;  // the estimator was not called
  const EngineeringQuantities none = ComputeEngineeringQuantities(not_run, kF0);
  for (const EngineeringValue& v : none.values) EXPECT_FALSE(v.determined);
}

// The budget (GUM): every determined quantity lists the fit's statistical part and, where the
// map reads them, the pick-off model's and the drift correction's components; what a session
// cannot evaluate is listed with a NaN size and a reason, never left out; u_c is the root sum of
// squares of the evaluated ones; a declared bound on the unmodelled coupling adds its component.
TEST(EngineeringQuantitiesTest, TheBudgetNamesEveryComponentAndCombinesTheEvaluatedOnes) {
  const EstimateSummary s = EstimateMaximumLikelihood(Session(AnisotropicTruth(), 11));
  ASSERT_TRUE(s.IsUsable());
  const auto find = [](const EngineeringValue& v, std::string_view source) {
    for (const UncertaintyComponent& c : v.budget)
      if (c.source == source) return &c;
    return static_cast<const UncertaintyComponent*>(nullptr);
  };
  const EngineeringQuantities e = ComputeEngineeringQuantities(s, kF0);
  for (std::size_t k = 1; k < kEngineeringQuantityCount; ++k) {
    const EngineeringValue& v = e.values[k];
    SCOPED_TRACE(std::string(kEngineeringQuantities[k].name));
    ASSERT_TRUE(v.determined);
    ASSERT_NE(find(v, "fit (statistical)"), nullptr);
    EXPECT_DOUBLE_EQ(find(v, "fit (statistical)")->standard_uncertainty, v.statistical_std);
    double sum = 0.0;
    for (const UncertaintyComponent& c : v.budget) {
      if (std::isfinite(c.standard_uncertainty)) {
        sum += c.standard_uncertainty * c.standard_uncertainty;
      } else {
        EXPECT_FALSE(c.note.empty()) << c.source;
      }
    }
    EXPECT_NEAR(v.std, std::sqrt(sum), 1e-12 * v.std);
    EXPECT_GE(v.std, v.statistical_std);
  }
  // The axes and the damping split read the pick-off's frame; τ does not, but reads the drift.
  EXPECT_NE(find(e[Q::kDampingSplit], "pick-off model: cross-talk stage"), nullptr);
  EXPECT_NE(find(e[Q::kFrequencyAxis], "pick-off model: cross-talk stage"), nullptr);
  EXPECT_EQ(find(e[Q::kDecayTime], "pick-off model: cross-talk stage"), nullptr);
  ASSERT_NE(find(e[Q::kDecayTime], "frequency drift correction"), nullptr);
  // The simulation records no Ω uncertainty: Ω taken as exact is named, with what 1e-6 rad/s of
  // one run's Ω would do (k reads Ω directly: about 1e-6/|Ω| of k at the smallest |Ω| = 0.1).
  ASSERT_FALSE(s.omega_sensitivity.empty());
  const UncertaintyComponent* omega = find(e[Q::kAngularGain], "Ω metrology");
  ASSERT_NE(omega, nullptr);
  EXPECT_TRUE(std::isnan(omega->standard_uncertainty));
  EXPECT_NE(omega->note.find("1e-6 rad/s"), std::string::npos) << omega->note;
  // No bound declared: the component is named and not evaluated.
  const UncertaintyComponent* undeclared =
      find(e[Q::kDampingAxis], "pick-off model: unmodelled antisymmetric coupling");
  ASSERT_NE(undeclared, nullptr);
  EXPECT_TRUE(std::isnan(undeclared->standard_uncertainty));
  EXPECT_NE(undeclared->note.find("no bound declared"), std::string::npos);
  // Declared: a frame-angle bound b turns the axes by up to b/2 rad on the shell (rectangular).
  EngineeringOptions options;
  options.unmodelled_coupling_bound_rad = 1e-3;
  const EngineeringQuantities bounded = ComputeEngineeringQuantities(s, kF0, options);
  const UncertaintyComponent* declared =
      find(bounded[Q::kFrequencyAxis], "pick-off model: unmodelled antisymmetric coupling");
  ASSERT_NE(declared, nullptr);
  // The real part turns the axis by b/2 on the shell; the imaginary part barely moves it.
  EXPECT_NEAR(declared->standard_uncertainty, 0.5e-3 * 180.0 / kPi / std::sqrt(3.0), 1e-4);
  EXPECT_GT(bounded[Q::kFrequencyAxis].std, e[Q::kFrequencyAxis].std);
  EXPECT_FALSE(bounded.BudgetReport().empty());
}

}  // namespace
}  // namespace hrgbench::estimator
