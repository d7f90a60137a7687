// Limits written in the field's units (tau_s, q_factor, frequency_split_mhz, ...): read from a
// limits file, judged on the engineering quantities, NOT EVALUATED when a quantity is not
// determined (held parameter, unknown f0, the axis of a split that is noise); and the verdict as
// the record carries it (VerdictJson).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "hrgbench/analysis/verdict.hpp"
#include "hrgbench/analysis/verdict_json.hpp"

namespace hrgbench::bench {
namespace {

using estimator::EngineeringQuantity;
using estimator::EstimateSummary;

// A unit with τ = 1000 s (δ1 = −1e-3), a frequency split of 0.5 mHz (δ5 = π·Δf = 1.5708e-6 rad/s,
// 157 of its std: significant) on the model's axis 0 and no damping split (δ3 = δ4 = 0 ± 1e-6:
// noise). Covariance diagonal: the std of each δ and ξ.
EstimateSummary Unit() {
  EstimateSummary s;
  s.method = "ml";
  s.termination = estimator::Termination::kConverged;
  s.delta << -1e-3, 0.3, 0.0, 0.0, std::numbers::pi * 0.5e-3, 0.0;
  s.delta_std << 1e-6, 1e-8, 1e-6, 1e-6, 1e-8, 1e-8;
  s.delta_estimated = {true, true, true, true, true, true};
  s.xi << 0.01, 0.0, 0.0, 0.0;
  s.xi_std = estimator::Xi::Constant(1e-5);
  s.xi_estimated = estimator::kAllXi;
  s.covariance = Eigen::MatrixXd::Zero(10, 10);
  for (int i = 0; i < 6; ++i) s.covariance(i, i) = s.delta_std[i] * s.delta_std[i];
  for (int i = 0; i < 4; ++i) s.covariance(6 + i, 6 + i) = 1e-10;
  s.residual_rms = 1e-4;
  s.noise_sigma = 1e-4;
  estimator::RunFitDiagnostics d;
  d.run_id = 1;
  d.samples = 100000;
  d.residual_ratio = 1.0;
  d.whiteness_z = 0.1;
  s.diagnostics.runs.push_back(d);
  return s;
}

LimitsConfig Limits(const char* lines) {
  auto limits = ParseLimitsConfig(std::string("[limits]\nname = \"t\"\n") + lines, "l.toml");
  EXPECT_TRUE(limits.has_value()) << limits.error().ToString();
  return limits.value_or(LimitsConfig{});
}

TEST(EngineeringLimits, AreReadUnderTheEstimatorsNames) {
  const LimitsConfig limits =
      Limits("tau_s = [500.0, 2000.0]\nq_factor = [1e6, 1e8]\nfrequency_axis_deg = [-5.0, 5.0]\n");
  ASSERT_EQ(limits.limits.size(), 3u);
  EXPECT_EQ(EngineeringOf(limits.limits[0].quantity), EngineeringQuantity::kDecayTime);
  EXPECT_EQ(ToString(limits.limits[1].quantity), "q_factor");
  EXPECT_EQ(LimitOf(EngineeringQuantity::kFrequencyAxis), limits.limits[2].quantity);
  EXPECT_FALSE(EngineeringOf(LimitedQuantity::kNoiseSigma).has_value());
  const auto unknown = ParseLimitsConfig("[limits]\nname = \"t\"\ntau = [1.0, 2.0]\n", "l.toml");
  ASSERT_FALSE(unknown.has_value());
  EXPECT_NE(unknown.error().ToString().find("tau_s"), std::string::npos)  // the valid keys listed
      << unknown.error().ToString();
}

TEST(EngineeringLimits, AreJudgedInTheFieldsUnits) {
  const EstimateSummary s = Unit();
  const auto engineering = estimator::ComputeEngineeringQuantities(s, 5000.0);
  // τ = 1000 s, Q = π·5000·1000 = 1.5708e7, Δf = 0.5 mHz, axis on the shell 0°.
  const Verdict pass =
      EvaluateLimits(Limits("tau_s = [900.0, 1100.0]\nq_factor = [1.5e7, 1.6e7]\n"
                            "frequency_split_mhz = [0.4, 0.6]\nfrequency_axis_deg = [-1.0, 1.0]\n"),
                     s, engineering);
  EXPECT_EQ(pass.overall, LimitStatus::kPass) << pass.Report();
  EXPECT_NEAR(pass.results[1].value, std::numbers::pi * 5e6, 1.0);
  EXPECT_NEAR(pass.results[0].std, 1.0, 1e-3);  // σ(τ) = σ(δ1)/δ1² = 1e-6/1e-6 s

  const Verdict fail = EvaluateLimits(Limits("frequency_split_mhz = [0.0, 0.3]\n"), s, engineering);
  EXPECT_EQ(fail.overall, LimitStatus::kFail);
  EXPECT_NE(fail.results[0].message.find("frequency_split_mhz = 0.5"), std::string::npos)
      << fail.results[0].message;
}

TEST(EngineeringLimits, WhatIsNotDeterminedIsNotEvaluated) {
  const EstimateSummary s = Unit();
  // The damping split is noise (χ² ≈ 0): its axis cannot be judged. Without f0, neither can Q.
  const Verdict verdict = EvaluateLimits(
      Limits("q_factor = [1e6, 1e8]\ndamping_axis_deg = [-45.0, 45.0]\ntau_s = [900.0, 1100.0]\n"),
      s, estimator::ComputeEngineeringQuantities(s, estimator::kNaN));
  EXPECT_EQ(verdict.overall, LimitStatus::kNotEvaluated);
  ASSERT_EQ(verdict.results.size(), 3u);  // in the order of LimitedQuantity: tau_s, q_factor, axis
  EXPECT_EQ(verdict.results[0].status, LimitStatus::kPass);
  EXPECT_EQ(verdict.results[1].status, LimitStatus::kNotEvaluated);
  EXPECT_NE(verdict.results[1].message.find("resonant frequency is unknown"), std::string::npos);
  EXPECT_EQ(verdict.results[2].status, LimitStatus::kNotEvaluated);
  EXPECT_NE(verdict.results[2].message.find("not significantly different from zero"),
            std::string::npos)
      << verdict.results[2].message;
}

TEST(EngineeringLimits, TheRecordCarriesEveryLimitAndFitCheck) {
  const EstimateSummary s = Unit();
  const Verdict verdict =
      EvaluateLimits(Limits("tau_s = [900.0, 1100.0]\nq_factor = [1e6, 1e8]\n"), s,
                     estimator::ComputeEngineeringQuantities(s, estimator::kNaN));
  const nlohmann::json j = VerdictJson(verdict);
  EXPECT_EQ(j["overall"], "NOT EVALUATED");
  EXPECT_EQ(j["fit_acceptable"], true);
  ASSERT_EQ(j["limits"].size(), 2u);
  EXPECT_EQ(j["limits"][0]["quantity"], "tau_s");
  EXPECT_EQ(j["limits"][0]["status"], "PASS");
  EXPECT_DOUBLE_EQ(j["limits"][0]["value"].get<double>(), 1000.0);
  EXPECT_EQ(j["limits"][0]["min"], 900.0);
  EXPECT_TRUE(j["limits"][1]["value"].is_null());  // not evaluated: no NaN in JSON
  EXPECT_EQ(j["limits"][1]["status"], "NOT EVALUATED");
  ASSERT_EQ(j["fit_checks"].size(), verdict.fit_checks.size());
  EXPECT_EQ(j["fit_checks"][0]["run"], 1);
  EXPECT_EQ(j["fit_checks"][0]["name"], "residual_ratio");
}

}  // namespace
}  // namespace hrgbench::bench
