// Decisions with guard bands on simulated units (issue 26 §2, config/decision_rule.hpp): units
// drawn good, marginal and bad in the gain mismatch ξ1 around the example limits' ξ1 = [−0.02,
// 0.02] (bench_configs/limits-example.toml), each measured by the paper's sequence (the design
// on which the issue saw a good unit FAIL) and decided by each rule. Prints Markdown tables: per
// rule and class, how many units were accepted, rejected, sent to retest, not judged, and the
// false-accept and false-reject rates (a unit's truth against the limit decides which is false).
//
//   guard_band_decision_table [--units N] [--design paper|production] [--sigma S] [--seed N]
//
// Default: 200 units per class, the paper's design (5 free runs of 10 s at 100 Hz, |Ω| ≤ 1e-4
// rad/s), σ = 1e-4 (the simulated station's pick-off noise, bench_configs/station-sim.toml).
// The truth: δ = (−0.001, 0.3, 0, 0, 0, 0), ξ = (ξ1, 0, 0, 0) with ξ1 drawn per unit:
//   good      ξ1 uniform in [−0.01, 0.01]               (at most half the limit)
//   marginal  |ξ1| uniform in [0.015, 0.025], random sign (about half conforming)
//   bad       |ξ1| uniform in [0.03, 0.05], random sign
// A unit is measured by the estimator on simulated free runs (estimator::SimulateRuns +
// EstimateMaximumLikelihood), not by a whole bench session: the decision only needs the
// estimate and its std, and 600 sessions through the simulated station would cost hours of CPU.
// The judge is the bench's own (EvaluateLimits) on the example file's ξ1 limit alone, so the other
// limits (which the paper's design does not resolve) do not mix into the rates. A retest
// measures the unit again with fresh noise; under the retest rule a unit still undecided after
// one retest is rejected (the table says how many).

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "hrgbench/analysis/verdict.hpp"
#include "hrgbench/config/limits_config.hpp"
#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/simulation.hpp"
#include "out_of_model.hpp"

namespace {

using namespace hrgbench;  // NOLINT(google-build-using-namespace): a one-file program

std::vector<estimator::RunPlan> PaperPlans() {
  std::vector<estimator::RunPlan> plans;
  for (int k = 1; k <= 5; ++k) {
    estimator::RunPlan p;
    p.omega_rad_s = -1e-4 + 5e-5 * (k - 1);
    p.a = 1.0;
    p.b = -0.4 + 0.2 * (k - 1);
    p.theta_rad = M_PI / 7.0 * (k - 1);
    p.sample_rate_hz = 100.0;
    p.duration_s = 10.0;
    plans.push_back(p);
  }
  return plans;
}

struct Measurement {
  double value = NAN, std = NAN;
};

struct Rule {
  const char* name;
  bench::DecisionRule decision;
};

struct Tally {
  int accepted = 0, rejected = 0, retest = 0, not_judged = 0;
  int false_accept = 0, false_reject = 0;
  // After one retest (retest rule only): accepted, rejected and still undecided (then rejected).
  int after_accepted = 0, after_rejected = 0, after_still_undecided = 0, after_not_judged = 0;
  int after_false_accept = 0, after_false_reject = 0;
};

}  // namespace

int main(int argc, char** argv) {
  int units = 200;
  std::string design = "paper";
  double sigma = 1e-4;
  std::uint64_t seed = 2611;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--units") == 0) {
      units = std::atoi(argv[i + 1]);
    } else if (std::strcmp(argv[i], "--design") == 0) {
      design = argv[i + 1];
    } else if (std::strcmp(argv[i], "--sigma") == 0) {
      sigma = std::atof(argv[i + 1]);
    } else if (std::strcmp(argv[i], "--seed") == 0) {
      seed = std::strtoull(argv[i + 1], nullptr, 10);
    } else {
      std::fprintf(stderr,
                   "usage: %s [--units N] [--design paper|production] [--sigma S] [--seed N]\n",
                   argv[0]);
      return 4;
    }
  }
  if (units < 1 || !(sigma > 0) || (design != "paper" && design != "production")) {
    std::fprintf(stderr, "units >= 1, sigma > 0, design paper or production\n");
    return 4;
  }
  const std::filesystem::path limits_file =
      std::filesystem::path(HRGBENCH_SOURCE_DIR) / "bench_configs" / "limits-example.toml";
  auto example = bench::LoadLimitsConfig(limits_file);
  if (!example) {
    std::fprintf(stderr, "%s\n", example.error().ToString().c_str());
    return 4;
  }
  bench::LimitsConfig limits = *example;
  limits.limits.clear();
  for (const bench::ParameterLimit& l : example->limits)
    if (l.quantity == bench::LimitedQuantity::kXi1) limits.limits.push_back(l);
  if (limits.limits.size() != 1) {
    std::fprintf(stderr, "%s has no xi1 limit\n", limits_file.c_str());
    return 4;
  }
  const double lo = limits.limits[0].min, hi = limits.limits[0].max;
  const std::vector<estimator::RunPlan> plans =
      design == "paper" ? PaperPlans() : testing::ProductionPlans(10.0, 100.0);

  std::uint64_t next_noise_seed = seed * 1000003;
  const auto measure = [&](double xi1) {
    estimator::SimulationOptions truth;
    truth.delta << -1e-3, 0.3, 0.0, 0.0, 0.0, 0.0;
    truth.xi << xi1, 0.0, 0.0, 0.0;
    truth.sigma = sigma;
    truth.seed = ++next_noise_seed;
    estimator::MlOptions options;
    options.num_threads = 1;  // a shared machine: one core
    const estimator::EstimateSummary s =
        estimator::EstimateMaximumLikelihood(estimator::SimulateRuns(plans, truth), options);
    return s;
  };

  std::vector<Rule> rules;
  {
    bench::DecisionRule r;
    r.kind = bench::DecisionRuleKind::kSimpleAcceptance;
    r.max_uncertainty_ratio = 0.5;  // the bench's rule before [decision]
    rules.push_back({"simple_acceptance, U/T <= 0.5 (≈ the rule before)", r});
    r.max_uncertainty_ratio = 0.25;
    rules.push_back({"simple_acceptance, U/T <= 0.25", r});
    r = {};
    r.kind = bench::DecisionRuleKind::kGuardedAcceptanceReject;
    r.coverage_factor = 1.0;
    rules.push_back({"guarded_acceptance_reject, k = 1", r});
    r.coverage_factor = 2.0;
    rules.push_back({"guarded_acceptance_reject, k = 2", r});
    r.kind = bench::DecisionRuleKind::kGuardedAcceptanceRetest;
    rules.push_back({"guarded_acceptance_retest, k = 2 (example file)", r});
  }

  const char* kClasses[] = {"good", "marginal", "bad"};
  std::mt19937_64 draw(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<std::vector<Tally>> tally(rules.size(), std::vector<Tally>(3));
  int conforming[3] = {0, 0, 0};
  double std_sum = 0.0;
  int std_count = 0, unusable = 0;
  for (int c = 0; c < 3; ++c) {
    for (int n = 0; n < units; ++n) {
      const double sign = unit(draw) < 0.5 ? -1.0 : 1.0;
      const double xi1 = c == 0   ? -0.01 + 0.02 * unit(draw)
                         : c == 1 ? sign * (0.015 + 0.01 * unit(draw))
                                  : sign * (0.03 + 0.02 * unit(draw));
      const bool truly_conforming = xi1 >= lo && xi1 <= hi;
      conforming[c] += truly_conforming ? 1 : 0;
      const estimator::EstimateSummary first = measure(xi1);
      if (!first.IsUsable()) {
        ++unusable;
        continue;
      }
      std_sum += first.xi_std(0);
      ++std_count;
      // The retest's measurement, made only when some rule asks for it (same for every rule).
      std::optional<estimator::EstimateSummary> second;
      for (std::size_t r = 0; r < rules.size(); ++r) {
        limits.decision = rules[r].decision;
        const bench::LimitResult result = bench::EvaluateLimits(limits, first).results.at(0);
        Tally& t = tally[r][static_cast<std::size_t>(c)];
        const bool passed = result.status == bench::LimitStatus::kPass;
        const bool judged_out = result.status == bench::LimitStatus::kFail && !result.retest;
        if (passed) ++t.accepted;
        if (judged_out) ++t.rejected;
        if (result.retest) ++t.retest;
        if (result.status == bench::LimitStatus::kNotEvaluated) ++t.not_judged;
        if (passed && !truly_conforming) ++t.false_accept;
        if (judged_out && truly_conforming) ++t.false_reject;
        if (rules[r].decision.kind != bench::DecisionRuleKind::kGuardedAcceptanceRetest) continue;
        // Final decision after one retest.
        bool final_pass = passed, final_reject = judged_out;
        bool final_not_judged = result.status == bench::LimitStatus::kNotEvaluated;
        if (result.retest) {
          if (!second) second = measure(xi1);
          const bench::LimitResult again = bench::EvaluateLimits(limits, *second).results.at(0);
          final_pass = again.status == bench::LimitStatus::kPass;
          final_not_judged = again.status == bench::LimitStatus::kNotEvaluated;
          final_reject = !final_pass && !final_not_judged;
          if (again.retest) ++t.after_still_undecided;
        }
        if (final_not_judged) ++t.after_not_judged;
        if (final_pass) ++t.after_accepted;
        if (final_reject) ++t.after_rejected;
        if (final_pass && !truly_conforming) ++t.after_false_accept;
        if (final_reject && truly_conforming) ++t.after_false_reject;
      }
    }
  }

  std::printf(
      "%d units per class, %s design, sigma = %g, seed %llu; xi1 limit [%g, %g] from %s; "
      "mean reported std of xi1 %.4g; %d estimates not usable\n\n",
      units, design.c_str(), sigma, static_cast<unsigned long long>(seed), lo, hi,
      "bench_configs/limits-example.toml", std_count > 0 ? std_sum / std_count : NAN, unusable);
  std::printf("truly conforming: good %d, marginal %d, bad %d of %d each\n\n", conforming[0],
              conforming[1], conforming[2], units);
  std::printf(
      "| rule | class | accepted | rejected | retest | not judged | false accept | "
      "false reject |\n|---|---|---|---|---|---|---|---|\n");
  for (std::size_t r = 0; r < rules.size(); ++r) {
    for (int c = 0; c < 3; ++c) {
      const Tally& t = tally[r][static_cast<std::size_t>(c)];
      const int bad_units = units - conforming[c], good_units = conforming[c];
      const auto rate = [](int k, int n) {
        char text[48];
        if (n == 0)
          std::snprintf(text, sizeof(text), "%d (—)", k);
        else
          std::snprintf(text, sizeof(text), "%d (%.1f %%)", k, 100.0 * k / n);
        return std::string(text);
      };
      std::printf("| %s | %s | %d | %d | %d | %d | %s | %s |\n", rules[r].name, kClasses[c],
                  t.accepted, t.rejected, t.retest, t.not_judged,
                  rate(t.false_accept, bad_units).c_str(),
                  rate(t.false_reject, good_units).c_str());
    }
  }
  std::printf(
      "\nAfter one retest (guarded_acceptance_retest, k = 2; still undecided: rejected)\n\n");
  std::printf(
      "| class | accepted | rejected | of them still undecided | not judged (ERROR) | "
      "false accept | false reject |\n|---|---|---|---|---|---|---|\n");
  for (std::size_t r = 0; r < rules.size(); ++r) {
    if (rules[r].decision.kind != bench::DecisionRuleKind::kGuardedAcceptanceRetest) continue;
    for (int c = 0; c < 3; ++c) {
      const Tally& t = tally[r][static_cast<std::size_t>(c)];
      const int bad_units = units - conforming[c], good_units = conforming[c];
      std::printf("| %s | %d | %d | %d | %d | %d of %d | %d of %d |\n", kClasses[c],
                  t.after_accepted, t.after_rejected, t.after_still_undecided, t.after_not_judged,
                  t.after_false_accept, bad_units, t.after_false_reject, good_units);
    }
  }
  return 0;
}
