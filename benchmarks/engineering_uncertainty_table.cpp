// The engineering quantities' standard errors (delta method, engineering_quantities.hpp) against
// the scatter of many simulated sessions: prints a Markdown table, one row per quantity, with the
// truth, the mean estimate, the Monte Carlo std, the mean reported std and their ratio.
//
//   engineering_uncertainty_table [--seeds N] [--duration S] [--rate HZ]
//
// Default: 200 sessions of the production design shortened to 10 s a run at 100 Hz, σ = 1e-4,
// a resonator with τ = 1000 s, Δ(1/τ) = 4.5e-5 1/s, Δf = 0.115 mHz, all four ξ (the unit test's
// case, tests/unit/estimator/engineering_quantities_test.cpp, which asserts ±20 %).

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "hrgbench/estimator/engineering_quantities.hpp"
#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "out_of_model.hpp"

int main(int argc, char** argv) {
  using namespace hrgbench;  // NOLINT(google-build-using-namespace): a one-function program
  int seeds = 200;
  double duration_s = 10.0, rate_hz = 100.0;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--seeds") == 0)
      seeds = std::atoi(argv[i + 1]);
    else if (std::strcmp(argv[i], "--duration") == 0)
      duration_s = std::atof(argv[i + 1]);
    else if (std::strcmp(argv[i], "--rate") == 0)
      rate_hz = std::atof(argv[i + 1]);
    else {
      std::fprintf(stderr, "usage: %s [--seeds N] [--duration S] [--rate HZ]\n", argv[0]);
      return 4;
    }
  }
  if (seeds < 2 || !(duration_s > 0) || !(rate_hz > 0)) {
    std::fprintf(stderr, "seeds >= 2, duration and rate > 0\n");
    return 4;
  }
  constexpr double kF0 = 5000.0;
  estimator::SimulationOptions truth;
  truth.delta << -1e-3, 0.3, 2e-5, -1e-5, 3e-4, -2e-4;
  truth.xi << 0.01, -0.003, 0.002, 0.004;
  truth.sigma = 1e-4;
  const auto true_values = estimator::EngineeringValues(truth.delta, truth.xi, kF0);
  constexpr std::size_t kCount = estimator::kEngineeringQuantityCount;
  std::vector<std::vector<double>> values(kCount), variances(kCount);
  int undetermined = 0;
  for (int seed = 1; seed <= seeds; ++seed) {
    truth.seed = 7000 + static_cast<std::uint64_t>(seed);
    const auto runs = estimator::SimulateRuns(testing::ProductionPlans(duration_s, rate_hz), truth);
    const estimator::EstimateSummary s = estimator::EstimateMaximumLikelihood(runs);
    if (!s.IsUsable()) {
      std::fprintf(stderr, "seed %d: %s\n", seed, s.message.c_str());
      return 1;
    }
    const auto e = estimator::ComputeEngineeringQuantities(s, kF0);
    for (std::size_t k = 1; k < kCount; ++k) {
      if (!e.values[k].determined) {
        ++undetermined;
        continue;
      }
      values[k].push_back(e.values[k].value);
      // The fit's statistical part: the systematic ones do not scatter over seeds.
      variances[k].push_back(e.values[k].statistical_std * e.values[k].statistical_std);
    }
  }
  std::printf("%d sessions, 6 runs x %g s at %g Hz, sigma = 1e-4; %d undetermined values\n\n",
              seeds, duration_s, rate_hz, undetermined);
  std::printf(
      "| quantity | unit | truth | mean estimate | Monte Carlo std | reported statistical std | "
      "ratio |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (std::size_t k = 1; k < kCount; ++k) {
    const std::vector<double>& v = values[k];
    const double n = static_cast<double>(v.size());
    double mean = 0.0, scatter = 0.0, reported = 0.0;
    for (double x : v) mean += x / n;
    for (double x : v) scatter += (x - mean) * (x - mean) / (n - 1.0);
    for (double x : variances[k]) reported += x / n;
    scatter = std::sqrt(scatter);
    reported = std::sqrt(reported);
    const auto& info = estimator::kEngineeringQuantities[k];
    std::printf("| `%s` | %s | %.6g | %.6g | %.3g | %.3g | %.3f |\n",
                std::string(info.name).c_str(),
                info.unit.empty() ? "–" : std::string(info.unit).c_str(), true_values[k], mean,
                scatter, reported, reported / scatter);
  }
  return 0;
}
