// hrg-design PLAN.toml: the Cramér–Rao standard deviation of every parameter for a planned
// experiment, with ξ known, ξ1 unknown and all ξ unknown side by side, and what the plan cannot
// determine. A simulation spec is a plan (same file, same loader).

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "app/cli_exit.hpp"
#include "app/logging.hpp"
#include "hrgbench/analysis/estimate_report_json.hpp"
#include "hrgbench/config/sim_spec.hpp"
#include "hrgbench/estimator/cramer_rao.hpp"

namespace {

using namespace hrgbench;

// σ used when neither --sigma nor the plan gives one: the noise level docs/estimator/model.md
// quotes.
constexpr double kFallbackSigma = 1e-4;

struct Case {
  const char* key;    // JSON key
  const char* title;  // column title
  estimator::XiMask xi_unknown;
};
constexpr std::array<Case, 3> kCases = {{{"xi_known", "xi known", estimator::kNoXi},
                                         {"xi1_unknown", "xi1 unknown", estimator::kXi1Only},
                                         {"all_xi_unknown", "all xi unknown", estimator::kAllXi}}};

std::string Cell(double value) {
  if (!std::isfinite(value)) return "-";
  char text[32];
  std::snprintf(text, sizeof(text), "%.3e", value);
  return text;
}

nlohmann::json CaseJson(const estimator::CrlbResult& result, const estimator::XiMask& xi_unknown) {
  nlohmann::json delta_std = nlohmann::json::array();
  nlohmann::json xi_std = nlohmann::json::array();
  for (int i = 0; i < 6; ++i) delta_std.push_back(bench::NumberOrNull(result.delta_std(i)));
  for (int i = 0; i < 4; ++i) {
    xi_std.push_back(xi_unknown[static_cast<std::size_t>(i)] ? bench::NumberOrNull(result.xi_std(i))
                                                             : nlohmann::json());
  }
  const auto& id = result.identifiability;
  return {{"valid", result.valid},
          {"message", result.message},
          {"samples", result.samples},
          {"delta_std", delta_std},
          {"xi_std", xi_std},
          {"condition_number", bench::NumberOrNull(id.condition_number)},
          {"delta_identifiable", id.delta_identifiable},
          {"xi_identifiable", id.xi_identifiable},
          {"reasons", id.reasons}};
}

void PrintTable(const app::SimSpec& plan, double sigma,
                const std::array<estimator::CrlbResult, 3>& results) {
  std::printf("plan: %s (%zu runs), sigma = %g per channel\n", plan.file.string().c_str(),
              plan.runs.size(), sigma);
  std::printf(
      "Cramer-Rao standard deviation (absolute, and relative to |truth| where non-zero)\n\n");
  std::printf("%-8s %12s", "param", "truth");
  for (const Case& c : kCases) std::printf(" | %-23s", c.title);
  std::printf("\n");
  const auto row = [&](const std::string& name, double truth, auto std_of, auto known,
                       auto identifiable) {
    std::printf("%-8s %12.5g", name.c_str(), truth);
    for (std::size_t k = 0; k < kCases.size(); ++k) {
      if (known(k)) {
        std::printf(" | %-23s", "known");
        continue;
      }
      if (!identifiable(k)) {
        std::printf(" | %-23s", "not identifiable");
        continue;
      }
      const double s = std_of(k);
      const std::string rel = (truth != 0.0 && std::isfinite(s)) ? Cell(s / std::abs(truth)) : "";
      std::printf(" | %10s %12s", Cell(s).c_str(), rel.empty() ? "" : ("(" + rel + ")").c_str());
    }
    std::printf("\n");
  };
  for (int i = 0; i < 6; ++i) {
    row(
        std::string(estimator::kDeltaNames[static_cast<std::size_t>(i)]), plan.delta(i),
        [&](std::size_t k) { return results[k].delta_std(i); }, [](std::size_t) { return false; },
        [&](std::size_t k) {
          return results[k].identifiability.delta_identifiable[static_cast<std::size_t>(i)];
        });
  }
  for (int i = 0; i < 4; ++i) {
    row(
        std::string(estimator::kXiNames[static_cast<std::size_t>(i)]), plan.xi(i),
        [&](std::size_t k) { return results[k].xi_std(i); },
        [&](std::size_t k) { return !kCases[k].xi_unknown[static_cast<std::size_t>(i)]; },
        [&](std::size_t k) {
          return results[k].identifiability.xi_identifiable[static_cast<std::size_t>(i)];
        });
  }
  std::printf("%-8s %12s", "cond", "");
  for (const auto& r : results)
    std::printf(" | %-23s", Cell(r.identifiability.condition_number).c_str());
  std::printf("\n\nfindings:\n");
  // Each finding once, with the cases it applies to.
  std::vector<std::pair<std::string, std::string>> findings;  // reason, cases
  bool any = false;
  for (std::size_t k = 0; k < kCases.size(); ++k) {
    if (!results[k].valid) {
      std::printf("  [%s] bound not computed: %s\n", kCases[k].title, results[k].message.c_str());
      any = true;
    }
    for (const std::string& reason : results[k].identifiability.reasons) {
      auto it = std::find_if(findings.begin(), findings.end(),
                             [&](const auto& f) { return f.first == reason; });
      if (it == findings.end()) {
        findings.emplace_back(reason, kCases[k].title);
      } else {
        it->second += std::string(", ") + kCases[k].title;
      }
    }
  }
  for (const auto& [reason, cases] : findings) {
    std::printf("  [%s] %s\n", cases.c_str(), reason.c_str());
    any = true;
  }
  if (!any) std::printf("  every parameter is identifiable in every case\n");
}

int Run(const std::string& plan_path, double sigma_override, int phase_degree, bool json) {
  auto plan = app::LoadSimSpec(plan_path);
  if (!plan) {
    spdlog::error("{}", plan.error().ToString());
    return kExitBadInput;
  }
  double sigma = plan->sigma;
  if (sigma_override > 0.0) {
    sigma = sigma_override;
  } else if (sigma <= 0.0) {
    sigma = kFallbackSigma;
    spdlog::info("the plan is noise-free; bounds at sigma = {} (use --sigma to choose)", sigma);
  }

  std::array<estimator::CrlbResult, 3> results;
  bool all_valid = true;
  for (std::size_t k = 0; k < kCases.size(); ++k) {
    estimator::DesignSpec design;
    design.delta = plan->delta;
    design.xi = plan->xi;
    design.sigma = sigma;
    design.xi_unknown = kCases[k].xi_unknown;
    design.runs = plan->runs;
    design.phase_degree = phase_degree;
    results[k] = estimator::CramerRaoBound(design);
    all_valid = all_valid && results[k].valid;
  }

  if (json) {
    nlohmann::json out = {{"plan", plan->file.string()},
                          {"sigma", sigma},
                          {"phase_degree", phase_degree},
                          {"runs", plan->runs.size()},
                          {"truth",
                           {{"delta", std::vector<double>(plan->delta.begin(), plan->delta.end())},
                            {"xi", std::vector<double>(plan->xi.begin(), plan->xi.end())}}}};
    for (std::size_t k = 0; k < kCases.size(); ++k) {
      out["cases"][kCases[k].key] = CaseJson(results[k], kCases[k].xi_unknown);
    }
    std::cout << out.dump(1) << '\n';
  } else {
    PrintTable(*plan, sigma, results);
  }
  return all_valid ? kExitOk : kExitFail;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{
      "hrg-design: Cramer-Rao standard deviations of delta and xi for a planned experiment (a "
      "simulation spec is a plan), with xi known, xi1 unknown and all xi unknown, and the "
      "identifiability findings.\n"
      "sigma: --sigma, else the plan's noise.sigma, else 1e-4.\n"
      "Here 1: a bound could not be computed (the plan cannot determine what is asked; see "
      "findings); 4: bad command line or plan.\n" +
      std::string(hrgbench::kExitCodesHelp)};
  std::string plan_path;
  double sigma = 0.0;
  bool json = false;
  bool quiet = false;
  int phase_degree = estimator::DesignSpec{}.phase_degree;
  cli.add_option("plan", plan_path, "plan or simulation spec (TOML)")->required();
  cli.add_option("--phase-degree", phase_degree,
                 "degree of each run's common phase taken as unknown, as hrg-estimate does "
                 "(default 2; 0 = the model's own bound, the demodulation reference's phase known)")
      ->check(CLI::Range(0, 3));
  cli.add_option("--sigma", sigma, "noise std per channel of y (overrides the plan's)")
      ->check(CLI::PositiveNumber);
  cli.add_flag("--json", json, "print one JSON object instead of the table");
  hrgbench::app::AddCommonFlags(cli, &quiet);
  return hrgbench::app::ParseAndRun(cli, argc, argv, "hrg-design", quiet,
                                    [&] { return Run(plan_path, sigma, phase_degree, json); });
}
