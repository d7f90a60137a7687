// Monte Carlo on the paper's design at σ = 1e-4: the default estimator is efficient (its scatter
// matches the CRLB and its own reported std), the paper's estimator is not.
//
// Bounds: with N = 300 seeds the sample std has a relative standard error of 1/√(2(N−1)) = 4.1 %;
// the tests allow ±15 % (3.6 standard errors). The mean has standard error std/√N; ±4 of those.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "hrgbench/estimator/cramer_rao.hpp"
#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/paper_method.hpp"
#include "hrgbench/estimator/simulation.hpp"

namespace hrgbench::estimator {
namespace {

constexpr int kSeeds = 300;

std::vector<RunPlan> PaperDesign() {
  std::vector<RunPlan> plans;
  for (int k = 0; k < 5; ++k) {
    RunPlan p;
    p.a = 1.0;
    p.b = -0.4 + 0.2 * k;
    p.theta_rad = 3.141592653589793 / 7 * k;
    p.omega_rad_s = -1e-4 + 5e-5 * k;
    p.sample_rate_hz = 100.0;
    p.duration_s = 10.0;
    plans.push_back(p);
  }
  return plans;
}

struct Scatter {
  double mean = 0.0;
  double std_dev = 0.0;
};

Scatter Of(const std::vector<double>& v) {
  Scatter s;
  for (double x : v) s.mean += x;
  s.mean /= static_cast<double>(v.size());
  for (double x : v) s.std_dev += (x - s.mean) * (x - s.mean);
  s.std_dev = std::sqrt(s.std_dev / static_cast<double>(v.size() - 1));
  return s;
}

// The comparison with the paper is made on the paper's own terms: the model alone (a demodulation
// reference locked to the wave's phase, Ω exact), so ML runs without the common-phase nuisance and
// the bound is the model's. (With the nuisance, the default, the δ2 bound of this weak design is
// about 3× wider: CommonPhaseCostsLittleOnAStrongDesign below and docs/estimator/methods.md say
// why.)
TEST(StatisticsTest, MaximumLikelihoodIsEfficientAndThePaperIsNot) {
  SimulationOptions truth;
  truth.delta << -0.001, 0.3, 0, 0, 0, 0;
  truth.xi << 0.01, 0, 0, 0;
  truth.sigma = 1e-4;
  DesignSpec design;
  design.delta = truth.delta;
  design.xi = truth.xi;
  design.sigma = truth.sigma;
  design.runs = PaperDesign();
  design.phase_degree = 0;
  const CrlbResult crlb = CramerRaoBound(design);
  ASSERT_TRUE(crlb.valid);
  design.xi_unknown = kNoXi;
  const CrlbResult crlb_xi_known = CramerRaoBound(design);
  ASSERT_TRUE(crlb_xi_known.valid);
  MlOptions model_only;
  model_only.phase_degree = 0;
  MlOptions xi_known = model_only;
  xi_known.xi_estimated = kNoXi;
  xi_known.xi_fixed = truth.xi;

  std::vector<double> ml_d1, ml_d2, ml_xi1, ml_std_d2, ml_known_d2, paper_d2;
  int not_converged = 0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    truth.seed = static_cast<std::uint64_t>(seed);
    const std::vector<RunData> runs = SimulateRuns(design.runs, truth);
    const EstimateSummary ml = EstimateMaximumLikelihood(runs, model_only);
    if (!ml.Converged()) ++not_converged;
    ml_d1.push_back(ml.delta[kDamping]);
    ml_d2.push_back(ml.delta[kScaleFactor]);
    ml_xi1.push_back(ml.xi[kGainMismatch]);
    ml_std_d2.push_back(ml.delta_std[kScaleFactor]);
    ml_known_d2.push_back(EstimateMaximumLikelihood(runs, xi_known).delta[kScaleFactor]);
    paper_d2.push_back(EstimatePaper(runs).delta[kScaleFactor]);
  }
  EXPECT_EQ(not_converged, 0);
  const Scatter d1 = Of(ml_d1), d2 = Of(ml_d2), xi1 = Of(ml_xi1), paper = Of(paper_d2);
  const Scatter known = Of(ml_known_d2);
  const Scatter reported = Of(ml_std_d2);
  // Efficiency: scatter at the bound.
  EXPECT_NEAR(d1.std_dev / crlb.delta_std[kDamping], 1.0, 0.15);
  EXPECT_NEAR(d2.std_dev / crlb.delta_std[kScaleFactor], 1.0, 0.15);
  EXPECT_NEAR(xi1.std_dev / crlb.xi_std[kGainMismatch], 1.0, 0.15);
  // Honest error bars: the reported std agrees with the scatter.
  EXPECT_NEAR(reported.mean / d2.std_dev, 1.0, 0.15);
  // Unbiased.
  EXPECT_NEAR(d2.mean, 0.3, 4 * d2.std_dev / std::sqrt(kSeeds));
  EXPECT_NEAR(xi1.mean, 0.01, 4 * xi1.std_dev / std::sqrt(kSeeds));
  EXPECT_NEAR(known.std_dev / crlb_xi_known.delta_std[kScaleFactor], 1.0, 0.15);
  // The paper's estimator assumes ξ known (as 0). Against the bound and the ML fit with that same
  // knowledge it scatters δ2 about 3× more (MODEL.md: ~11 % efficiency, i.e. std ×3); and it is
  // worse even than ML that must also estimate all four ξ.
  EXPECT_GT(paper.std_dev / known.std_dev, 2.5);
  EXPECT_GT(paper.std_dev / crlb_xi_known.delta_std[kScaleFactor], 2.5);
  EXPECT_GT(paper.std_dev / d2.std_dev, 1.5);
  RecordProperty("ml_delta2_std", std::to_string(d2.std_dev));
  RecordProperty("crlb_delta2_std", std::to_string(crlb.delta_std[kScaleFactor]));
  RecordProperty("paper_delta2_std", std::to_string(paper.std_dev));
  std::printf(
      "delta2 std: ml all xi %.4g (reported %.4g, CRLB %.4g); ml xi known %.4g (CRLB %.4g); "
      "paper %.4g; xi1 std ml %.4g CRLB %.4g\n",
      d2.std_dev, reported.mean, crlb.delta_std[kScaleFactor], known.std_dev,
      crlb_xi_known.delta_std[kScaleFactor], paper.std_dev, xi1.std_dev,
      crlb.xi_std[kGainMismatch]);
}

}  // namespace
}  // namespace hrgbench::estimator

namespace hrgbench::estimator {
namespace {

// The default estimator, invariant to the demodulation reference's phase and frequency (a common
// phase of degree 2 per run), on the same design: at its own bound, the CRLB with that nuisance
// (3.1× the model's for δ2 here, docs/estimator/methods.md), with honest reported std.
TEST(StatisticsTest, TheInvariantEstimatorIsEfficientAtItsOwnBound) {
  SimulationOptions truth;
  truth.delta << -0.001, 0.3, 0, 0, 0, 0;
  truth.xi << 0.01, 0, 0, 0;
  truth.sigma = 1e-4;
  DesignSpec design;
  design.delta = truth.delta;
  design.xi = truth.xi;
  design.sigma = truth.sigma;
  design.runs = PaperDesign();
  ASSERT_EQ(design.phase_degree, MlOptions{}.phase_degree);
  const CrlbResult crlb = CramerRaoBound(design);
  ASSERT_TRUE(crlb.valid);
  std::vector<double> d1, d2, xi1, reported_d2;
  int flagged = 0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    truth.seed = static_cast<std::uint64_t>(seed);
    const EstimateSummary ml = EstimateMaximumLikelihood(SimulateRuns(design.runs, truth));
    ASSERT_TRUE(ml.IsUsable());
    if (!ml.diagnostics.Acceptable()) ++flagged;
    d1.push_back(ml.delta[kDamping]);
    d2.push_back(ml.delta[kScaleFactor]);
    xi1.push_back(ml.xi[kGainMismatch]);
    reported_d2.push_back(ml.delta_std[kScaleFactor]);
  }
  EXPECT_NEAR(Of(d1).std_dev / crlb.delta_std[kDamping], 1.0, 0.15);
  EXPECT_NEAR(Of(d2).std_dev / crlb.delta_std[kScaleFactor], 1.0, 0.15);
  EXPECT_NEAR(Of(xi1).std_dev / crlb.xi_std[kGainMismatch], 1.0, 0.15);
  EXPECT_NEAR(Of(reported_d2).mean / Of(d2).std_dev, 1.0, 0.15);
  EXPECT_NEAR(Of(d2).mean, 0.3, 4 * Of(d2).std_dev / std::sqrt(kSeeds));
  // 300 clean sessions of five runs: no false alarm expected (~1e-5 each).
  EXPECT_EQ(flagged, 0);
}

}  // namespace
}  // namespace hrgbench::estimator
