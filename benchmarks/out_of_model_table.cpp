// Out of its own model: how far each perturbation moves the estimate, in reported std, and whether
// the fit says so. Prints the Markdown table of docs/measurements/ ("Is the fit right?").
//
//   out_of_model_table [--seeds N] [--duration S] [--rate HZ] [--runs N] [--last-run-s S]
//                      [--false-alarm N]
//
// Each row simulates the production design (6 runs at ±0.1, ±0.3, ±1 rad/s, σ = 1e-4) with the
// estimator's own model, applies one perturbation (tests/support/out_of_model.hpp), and fits it
// twice (--runs N: only the design's first N runs, e.g. 2 at 20 s: the first point at which
// sequence-production-adaptive.toml may decide a unit after a run; --last-run-s 5: the last of them
// only its first 5 s, where its first look within run 2 may): "model only" (the estimator as it
// was: no common phase, Ω exact, no outlier removal, white-noise covariance) and "default"
// (MlOptions defaults). Per row and fit: the largest |estimate − truth|/std over the ten parameters
// (averaged over seeds, signed, with the parameter), the RMS of (estimate − truth)/std over
// parameters and seeds, the share beyond 3 std, and the share of sessions the fit flagged (a
// problem in diagnostics). --false-alarm N fits N clean sessions and counts the flagged ones.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/simulation.hpp"
#include "out_of_model.hpp"

namespace {

using hrgbench::estimator::EstimateSummary;
using hrgbench::estimator::MlOptions;
using hrgbench::estimator::RunData;

constexpr double kSigma = 1e-4;

struct Perturbation {
  std::string name;
  std::function<void(std::vector<RunData>*, std::uint64_t seed)> apply;  // noise included
};

struct Tally {
  double largest_sum[10] = {};
  double z2_sum = 0.0;
  int z_count = 0;
  int beyond3 = 0;
  int flagged = 0;
  int sessions = 0;
  double worst_ratio = 0.0;
  double worst_whiteness = -1e300;
};

double ParameterZ(const EstimateSummary& s, const hrgbench::estimator::SimulationOptions& truth,
                  int i) {
  if (i < 6) return (s.delta[i] - truth.delta[i]) / s.delta_std[i];
  return (s.xi[i - 6] - truth.xi[i - 6]) / s.xi_std[i - 6];
}

void Add(const EstimateSummary& s, const hrgbench::estimator::SimulationOptions& truth, Tally* t) {
  ++t->sessions;
  if (!s.diagnostics.problems.empty()) ++t->flagged;
  for (int i = 0; i < 10; ++i) {
    const double z = ParameterZ(s, truth, i);
    if (!std::isfinite(z)) continue;
    t->largest_sum[i] += z;
    t->z2_sum += z * z;
    ++t->z_count;
    if (std::abs(z) > 3.0) ++t->beyond3;
  }
  for (const auto& run : s.diagnostics.runs) {
    t->worst_ratio = std::max(t->worst_ratio, run.residual_ratio);
    t->worst_whiteness = std::max(t->worst_whiteness, run.whiteness_z);
  }
}

std::string Largest(const Tally& t) {
  static const char* names[10] = {"δ1", "δ2", "δ3", "δ4", "δ5", "δ6", "ξ1", "ξ2", "ξ3", "ξ4"};
  int worst = 0;
  for (int i = 1; i < 10; ++i)
    if (std::abs(t.largest_sum[i]) > std::abs(t.largest_sum[worst])) worst = i;
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%s %+.3g", names[worst],
                t.largest_sum[worst] / std::max(1, t.sessions));
  return buffer;
}

MlOptions ModelOnly() {
  MlOptions o;
  o.num_threads = 1;
  o.phase_degree = 0;
  o.omega_uncertainty = false;
  o.outlier_threshold_sigma = 0.0;
  o.covariance = MlOptions::Covariance::kWhite;
  return o;
}

MlOptions Default() {
  MlOptions o;
  o.num_threads = 1;
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 4;
  double duration = 100.0;
  double rate = 1000.0;
  int false_alarm = 0;
  int first_runs = 6;
  double last_run_s = 0.0;  // 0: the last run as long as the others
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--seeds"))
      seeds = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--duration"))
      duration = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--rate"))
      rate = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--runs"))
      first_runs = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--last-run-s"))
      last_run_s = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--false-alarm"))
      false_alarm = std::atoi(argv[i + 1]);
    else {
      std::fprintf(stderr, "unknown option %s\n", argv[i]);
      return 2;
    }
  }
  const auto truth = hrgbench::testing::ProductionTruth();
  auto plans = hrgbench::testing::ProductionPlans(duration, rate);
  if (first_runs < 1 || first_runs > static_cast<int>(plans.size())) {
    std::fprintf(stderr, "--runs %d: 1 to %zu\n", first_runs, plans.size());
    return 2;
  }
  plans.resize(static_cast<std::size_t>(first_runs));
  if (last_run_s > 0.0) plans.back().duration_s = std::min(plans.back().duration_s, last_run_s);
  const auto simulate = [&](std::uint64_t seed, const Perturbation& perturbation) {
    auto noise_free = truth;
    noise_free.sigma = 0.0;
    std::vector<RunData> runs = hrgbench::estimator::SimulateRuns(plans, noise_free);
    perturbation.apply(&runs, seed);
    return runs;
  };
  const auto white = [](std::vector<RunData>* runs, std::uint64_t seed) {
    for (std::size_t r = 0; r < runs->size(); ++r)
      hrgbench::testing::AddNoise(&(*runs)[r], kSigma, 0.0, seed * 100 + r);
  };

  if (false_alarm > 0) {
    Tally t;
    for (int seed = 1; seed <= false_alarm; ++seed) {
      const auto runs = simulate(static_cast<std::uint64_t>(seed), {"clean", white});
      const EstimateSummary s = hrgbench::estimator::EstimateMaximumLikelihood(runs, Default());
      Add(s, truth, &t);
      for (const std::string& p : s.diagnostics.problems)
        std::printf("seed %d: %s\n", seed, p.c_str());
    }
    std::printf(
        "clean sessions: %d, flagged: %d; RMS z %.3f, beyond 3 std %d of %d; worst residual "
        "ratio %.4f, worst whiteness z %.2f\n",
        t.sessions, t.flagged, std::sqrt(t.z2_sum / std::max(1, t.z_count)), t.beyond3, t.z_count,
        t.worst_ratio, t.worst_whiteness);
    return 0;
  }

  const std::vector<Perturbation> rows = {
      {"none (in model)", white},
      {"Ω of run 1 off by 1e-6 rad/s, σ_Ω not recorded",
       [&](std::vector<RunData>* runs, std::uint64_t seed) {
         white(runs, seed);
         (*runs)[0].omega_rad_s += 1e-6;
       }},
      {"Ω of run 1 off by 1e-6 rad/s, σ_Ω = 1e-6 recorded",
       [&](std::vector<RunData>* runs, std::uint64_t seed) {
         white(runs, seed);
         (*runs)[0].omega_rad_s += 1e-6;
         for (RunData& r : *runs) r.omega_std_rad_s = 1e-6;
       }},
      {"Ω of run 1 off by 1e-5 rad/s, σ_Ω = 1e-6 recorded",
       [&](std::vector<RunData>* runs, std::uint64_t seed) {
         white(runs, seed);
         (*runs)[0].omega_rad_s += 1e-5;
         for (RunData& r : *runs) r.omega_std_rad_s = 1e-6;
       }},
      {"common frequency ramp 0 → 3e-4 rad/s over each run",
       [&](std::vector<RunData>* runs, std::uint64_t seed) {
         for (RunData& r : *runs) hrgbench::testing::ApplyFrequencyRamp(&r, 3e-4);
         white(runs, seed);
       }},
      {"AR(1) noise, ρ = 0.9, same marginal σ",
       [&](std::vector<RunData>* runs, std::uint64_t seed) {
         for (std::size_t r = 0; r < runs->size(); ++r)
           hrgbench::testing::AddNoise(&(*runs)[r], kSigma, 0.9, seed * 100 + r);
       }},
      {"ten ±100σ spikes in run 1",
       [&](std::vector<RunData>* runs, std::uint64_t seed) {
         white(runs, seed);
         hrgbench::testing::AddSpikes(&(*runs)[0], 10, 100.0 * kSigma, seed + 7);
       }},
  };

  std::printf(
      "Production design (its first %d runs), σ = %g, %g s per run (the last %g s) at %g Hz, %d "
      "seeds per row.\n\n",
      first_runs, kSigma, duration, plans.back().duration_s, rate, seeds);
  std::printf(
      "| perturbation | fit | largest mean error, std | RMS error, std | beyond 3 std | "
      "flagged | worst residual ratio | worst whiteness z |\n|---|---|---|---|---|---|---|---|\n");
  for (const Perturbation& row : rows) {
    for (int kind = 0; kind < 2; ++kind) {
      Tally t;
      for (int seed = 1; seed <= seeds; ++seed) {
        const auto runs = simulate(static_cast<std::uint64_t>(seed), row);
        const EstimateSummary s = hrgbench::estimator::EstimateMaximumLikelihood(
            runs, kind == 0 ? ModelOnly() : Default());
        Add(s, truth, &t);
      }
      std::printf("| %s | %s | %s | %.2f | %d %% | %d of %d | %.3f | %.1f |\n", row.name.c_str(),
                  kind == 0 ? "model only" : "default", Largest(t).c_str(),
                  std::sqrt(t.z2_sum / std::max(1, t.z_count)),
                  static_cast<int>(std::lround(100.0 * t.beyond3 / std::max(1, t.z_count))),
                  t.flagged, t.sessions, t.worst_ratio, t.worst_whiteness);
      std::fflush(stdout);
    }
  }
  return 0;
}
