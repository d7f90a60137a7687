// Is the reported std of ξ1 (the gain mismatch, ≈ −2·ξ1) honest under noise the slow model does not
// describe? Monte Carlo on the estimator's own simulation (estimator/simulation.hpp: the production
// plan shortened to 6 × 10 s at 100 Hz, σ = 1e-4 on channel 1) with noise structured as a physical
// pick-off might give it: channel 2's noise `--ratio` times channel 1's, channel 2's in-phase noise
// correlated `--corr` with channel 1's (and quadrature with quadrature), channel 2's quadrature
// correlated `--cross` with channel 1's in-phase (a 90° coupling), and a common phase jitter of
// `--phase-noise` rad per sample (the reference). Prints ξ1's scatter over the seeds against its
// mean reported std, with the white and with the sandwich covariance
// (docs/measurements/2026-11-26-gain-mismatch-std.md).
//
// Usage: build/bin/gain_mismatch_std_table [--seeds 150] [--ratio 1] [--corr 0] [--cross 0]
//            [--phase-noise 0]

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numbers>
#include <random>
#include <vector>

#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/simulation.hpp"

namespace est = hrgbench::estimator;

int main(int argc, char** argv) {
  int seeds = 150;
  double ratio = 1.0, corr = 0.0, cross = 0.0, phase_noise = 0.0;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--seeds") == 0) seeds = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--ratio") == 0) ratio = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--corr") == 0) corr = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--cross") == 0) cross = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--phase-noise") == 0) phase_noise = std::atof(argv[i + 1]);
  }
  if (seeds < 3 || std::abs(corr) > 1.0 || std::abs(cross) > 1.0 ||
      corr * corr + cross * cross > 1.0) {
    std::fprintf(stderr, "need --seeds ≥ 3 and corr² + cross² ≤ 1\n");
    return 2;
  }
  constexpr double kSigma = 1e-4;
  est::SimulationOptions truth;
  truth.delta << -1.25e-3, 0.3, 1e-5, -1e-5, 6e-4, 2e-4;
  truth.xi << 0.01, 0.001, 0.001, 0.001;
  std::vector<est::RunPlan> plans;
  const double omegas[6] = {0.1, -0.1, 0.3, -0.3, 1.0, -1.0};
  for (int r = 0; r < 6; ++r) {
    est::RunPlan p;
    p.omega_rad_s = omegas[r];
    p.a = 1.0;
    p.b = 0.1 * (r % 3);
    p.theta_rad = r * std::numbers::pi / 12.0;
    p.sample_rate_hz = 100.0;
    p.duration_s = 10.0;
    plans.push_back(p);
  }
  const std::vector<est::RunData> clean = est::SimulateRuns(plans, truth);
  const double own = std::sqrt(std::max(0.0, 1.0 - corr * corr - cross * cross));
  for (const auto covariance :
       {est::MlOptions::Covariance::kWhite, est::MlOptions::Covariance::kSandwich}) {
    est::MlOptions ml;
    ml.num_threads = 1;
    ml.covariance = covariance;
    double sum = 0.0, sum2 = 0.0, reported = 0.0;
    int n = 0;
    for (int seed = 1; seed <= seeds; ++seed) {
      std::vector<est::RunData> runs = clean;
      std::mt19937_64 rng(static_cast<std::uint64_t>(seed));
      std::normal_distribution<double> normal(0.0, 1.0);
      for (est::RunData& run : runs) {
        for (Eigen::Index k = 0; k < run.size(); ++k) {
          const double jitter = phase_noise * normal(rng);
          for (int ch = 0; ch < 2; ++ch) {
            const double re = run.y(2 * ch, k), im = run.y(2 * ch + 1, k);
            run.y(2 * ch, k) = re - jitter * im;
            run.y(2 * ch + 1, k) = im + jitter * re;
          }
          const double i1 = normal(rng), q1 = normal(rng), i2 = normal(rng), q2 = normal(rng);
          run.y(0, k) += kSigma * i1;
          run.y(1, k) += kSigma * q1;
          run.y(2, k) += ratio * kSigma * (corr * i1 - cross * q1 + own * i2);
          run.y(3, k) += ratio * kSigma * (corr * q1 + cross * i1 + own * q2);
        }
      }
      const est::EstimateSummary s = est::EstimateMaximumLikelihood(runs, ml);
      if (!s.IsUsable()) continue;
      sum += s.xi[0];
      sum2 += s.xi[0] * s.xi[0];
      reported += s.xi_std[0];
      ++n;
    }
    const double mean = sum / n;
    const double scatter = std::sqrt(std::max(0.0, (sum2 - n * mean * mean) / (n - 1)));
    std::printf(
        "ratio %.2f, corr %.2f, cross %.2f, phase noise %.2g rad, %s covariance: ξ1 scatter / "
        "reported std %.3f ± %.3f (%d sessions)\n",
        ratio, corr, cross, phase_noise,
        covariance == est::MlOptions::Covariance::kWhite ? "white" : "sandwich",
        scatter / (reported / n), 1.0 / std::sqrt(2.0 * (n - 1)), n);
  }
  return 0;
}
