// Speed and accuracy of the estimators, printed as Markdown tables (kept in docs/measurements/):
//  1. the paper's design (5 runs × 10 s × 100 Hz): the paper's methods against maximum likelihood,
//     noise-free and at σ = 1e-4 over several seeds, with the time ratio grid / ML;
//  2. a production-size session: 6 runs × 100 s × 1 kHz = 600 000 samples;
//  3. how the ML time grows with the number of samples.
// Times are the median of repeated runs, wall clock, on whatever machine runs this.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/paper_method.hpp"
#include "hrgbench/estimator/simulation.hpp"

namespace {

using namespace hrgbench::estimator;

double MedianMs(int repeats, const std::function<void()>& fn) {
  std::vector<double> ms;
  for (int i = 0; i < repeats; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    fn();
    ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  return ms[ms.size() / 2];
}

std::vector<RunPlan> PaperDesign() {
  std::vector<RunPlan> plans;
  for (int k = 0; k < 5; ++k) {
    RunPlan p;
    p.b = -0.4 + 0.2 * k;
    p.theta_rad = std::numbers::pi / 7 * k;
    p.omega_rad_s = -1e-4 + 5e-5 * k;
    plans.push_back(p);
  }
  return plans;
}

std::vector<RunPlan> RateTableDesign(double duration_s) {
  const double omegas[] = {0.1, -0.1, 0.3, -0.3, 1.0, -1.0};
  std::vector<RunPlan> plans;
  for (int k = 0; k < 6; ++k) {
    RunPlan p;
    p.omega_rad_s = omegas[k];
    p.b = 0.1 * (k % 3);
    p.theta_rad = k * std::numbers::pi / 12;
    p.sample_rate_hz = 1000.0;
    p.duration_s = duration_s;
    plans.push_back(p);
  }
  return plans;
}

struct Method {
  const char* name;
  std::function<EstimateSummary(const std::vector<RunData>&)> run;
};

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::string(argv[1]) == "--quick";
  const int seeds = quick ? 2 : 8;

  SimulationOptions paper_truth;
  paper_truth.delta << -0.001, 0.3, 0, 0, 0, 0;
  paper_truth.xi << 0.01, 0, 0, 0;
  MlOptions ml_xi1;
  ml_xi1.xi_estimated = kXi1Only;
  const std::vector<Method> methods = {
      {"paper (OLS, line-fit derivative, no ξ)", [](const auto& r) { return EstimatePaper(r); }},
      {"paper ξ1 grid (10 001 points)", [](const auto& r) { return EstimatePaperXiGrid(r); }},
      {"ml, ξ1", [&](const auto& r) { return EstimateMaximumLikelihood(r, ml_xi1); }},
      {"ml, all four ξ (default)", [](const auto& r) { return EstimateMaximumLikelihood(r); }},
  };

  std::printf("## 1. The paper's design: 5 runs × 10 s × 100 Hz (5 000 samples)\n\n");
  std::printf("Noise-free; σ = 1e-4: std of δ2 and RMS of ‖δ*−δ0‖/‖δ0‖ over %d seeds.\n\n", seeds);
  std::printf(
      "| method | time, ms | δ2 (noise-free) | ξ1 (noise-free) | ‖δ*−δ0‖/‖δ0‖ noise-free | δ2 std, "
      "σ=1e-4 | ‖δ*−δ0‖/‖δ0‖ RMS, σ=1e-4 |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|\n");
  const std::vector<RunData> clean = SimulateRuns(PaperDesign(), paper_truth);
  std::vector<double> times;
  for (const Method& m : methods) {
    EstimateSummary s;
    const bool slow = std::string(m.name).find("grid") != std::string::npos;
    const double ms = MedianMs(slow ? 1 : 5, [&] { s = m.run(clean); });
    times.push_back(ms);
    const double dev = (s.delta - paper_truth.delta).norm() / paper_truth.delta.norm();
    double sum = 0, sum2 = 0, dev2 = 0;
    SimulationOptions noisy = paper_truth;
    noisy.sigma = 1e-4;
    for (int seed = 1; seed <= seeds; ++seed) {
      noisy.seed = static_cast<std::uint64_t>(seed);
      const EstimateSummary n = m.run(SimulateRuns(PaperDesign(), noisy));
      sum += n.delta[kScaleFactor];
      sum2 += n.delta[kScaleFactor] * n.delta[kScaleFactor];
      const double d = (n.delta - paper_truth.delta).norm() / paper_truth.delta.norm();
      dev2 += d * d;
    }
    const double mean = sum / seeds;
    const double std_dev = std::sqrt(std::max(0.0, (sum2 - seeds * mean * mean) / (seeds - 1)));
    std::printf("| %s | %.2f | %.7f | %.7f | %.2e | %.2e | %.2e |\n", m.name, ms,
                s.delta[kScaleFactor], s.xi[kGainMismatch], dev, std_dev, std::sqrt(dev2 / seeds));
  }
  std::printf("\nSpeed ratio, paper ξ1 grid / ml with all four ξ: **%.0f×**\n\n",
              times[1] / times[3]);

  std::printf(
      "## 2. Production-size session: 6 runs × 100 s × 1 kHz = 600 000 samples, σ = 1e-4\n\n");
  std::printf(
      "| threads | ml (all ξ) time, ms | iterations | δ2 | δ2 std | ξ1 std "
      "|\n|---:|---:|---:|---:|---:|---:|\n");
  SimulationOptions table_truth;
  table_truth.delta << -0.0008, 0.31, -1e-6, 2e-6, -3e-6, 1e-6;
  table_truth.xi << -0.005, 0.002, -0.004, 0.007;
  table_truth.sigma = 1e-4;
  table_truth.seed = 7;
  const std::vector<RunData> production = SimulateRuns(RateTableDesign(100.0), table_truth);
  for (int threads : {0, 1}) {
    MlOptions options;
    options.num_threads = threads;
    EstimateSummary s;
    const double ms =
        MedianMs(quick ? 1 : 3, [&] { s = EstimateMaximumLikelihood(production, options); });
    std::printf("| %s | %.0f | %d | %.10f | %.2e | %.2e |\n", threads == 0 ? "all (2 here)" : "1",
                ms, s.iterations, s.delta[kScaleFactor], s.delta_std[kScaleFactor],
                s.xi_std[kGainMismatch]);
  }

  std::printf("\n## 3. Scaling with the number of samples (ml, all ξ, 6 runs at 1 kHz)\n\n");
  std::printf(
      "| run length, s | samples | time, ms | ns per sample | iterations "
      "|\n|---:|---:|---:|---:|---:|\n");
  for (double duration : {12.5, 25.0, 50.0, 100.0, 200.0}) {
    if (quick && duration > 50.0) break;
    const std::vector<RunData> runs = SimulateRuns(RateTableDesign(duration), table_truth);
    std::size_t n = 0;
    for (const RunData& r : runs) n += static_cast<std::size_t>(r.size());
    EstimateSummary s;
    const double ms = MedianMs(7, [&] { s = EstimateMaximumLikelihood(runs); });
    std::printf("| %.1f | %zu | %.0f | %.0f | %d |\n", duration, n, ms,
                1e6 * ms / static_cast<double>(n), s.iterations);
  }
  return 0;
}
