// hrg-compare DIR: the paper's method, the paper's ξ1 grid and maximum likelihood on one session,
// side by side with their wall time; the deviation from the truth when the session carries it.

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>

#include "app/cli_exit.hpp"
#include "app/logging.hpp"
#include "hrgbench/analysis/estimate_method.hpp"
#include "hrgbench/session/session.hpp"

namespace {

using namespace hrgbench;

// δ0 from session.json "simulation.delta", when present and well-formed.
std::optional<estimator::Delta> TruthDelta(const nlohmann::json& document) {
  const nlohmann::json* delta = nullptr;
  if (document.contains("simulation") && document["simulation"].is_object() &&
      document["simulation"].contains("delta")) {
    delta = &document["simulation"]["delta"];
  }
  if (delta == nullptr || !delta->is_array() || delta->size() != 6) return std::nullopt;
  estimator::Delta out;
  for (int i = 0; i < 6; ++i) {
    const auto& v = (*delta)[static_cast<std::size_t>(i)];
    if (!v.is_number()) return std::nullopt;
    out(i) = v.get<double>();
  }
  return out;
}

std::string Number(double value, const char* format) {
  if (!std::isfinite(value)) return "-";
  char text[32];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

int Run(const std::string& dir) {
  session::ReadOptions read_options;
  read_options.min_samples_per_run = std::max({bench::MinimumSamples(bench::Method::kMl),
                                               bench::MinimumSamples(bench::Method::kPaper),
                                               bench::MinimumSamples(bench::Method::kPaperXiGrid)});
  auto session = session::ReadSession(dir, read_options);
  if (!session) {
    std::cerr << session.error().ToString() << '\n';
    return kExitBadInput;
  }
  const std::vector<estimator::RunData> runs = session::ToRunData(*session);
  if (runs.empty()) {
    std::cerr << dir << ": no complete run to estimate from\n";
    return kExitBadInput;
  }
  for (const std::string& w : session->warnings) spdlog::warn("{}", w);
  const std::optional<estimator::Delta> truth = TruthDelta(session->document);

  struct Row {
    const char* label;
    bench::MethodRequest request;
  };
  const auto request = [](bench::Method method, std::optional<estimator::XiMask> xi) {
    bench::MethodRequest r;
    r.method = method;
    r.xi = xi;
    return r;
  };
  const Row rows[] = {{"paper (no xi)", request(bench::Method::kPaper, std::nullopt)},
                      {"paper xi1 grid", request(bench::Method::kPaperXiGrid, std::nullopt)},
                      {"ML (all xi)", request(bench::Method::kMl, estimator::kAllXi)}};

  std::printf("session: %s (%zu runs)\n", dir.c_str(), runs.size());
  if (truth) {
    std::printf("truth:   delta2 = %.7f, |delta0| = %.7g\n", (*truth)(estimator::kScaleFactor),
                truth->norm());
  }
  std::printf("\n%-15s %12s %12s %14s %12s %9s  %s\n", "method", "delta2", "xi1", "|d*-d0|/|d0|",
              "resid RMS", "time [s]", "termination");
  bool all_usable = true;
  std::vector<std::string> warnings;
  for (const Row& row : rows) {
    spdlog::info("running {}", row.label);
    const bench::MethodResult result = bench::RunMethod(runs, row.request);
    const estimator::EstimateSummary& s = result.summary;
    all_usable = all_usable && s.IsUsable();
    const double deviation =
        (truth && s.IsUsable()) ? (s.delta - *truth).norm() / truth->norm() : estimator::kNaN;
    const double xi1 =
        s.xi_estimated[estimator::kGainMismatch] ? s.xi(estimator::kGainMismatch) : estimator::kNaN;
    std::printf("%-15s %12s %12s %14s %12s %9.3f  %s\n", row.label,
                Number(s.delta(estimator::kScaleFactor), "%.7f").c_str(),
                Number(xi1, "%.7f").c_str(), Number(deviation, "%.2e").c_str(),
                Number(s.residual_rms, "%.3e").c_str(), result.seconds,
                estimator::ToString(s.termination));
    for (const std::string& w : result.selection_warnings)
      warnings.push_back(std::string(row.label) + ": " + w);
    for (const std::string& w : s.warnings) warnings.push_back(std::string(row.label) + ": " + w);
  }
  std::printf(
      "\nresid RMS: ML of y per channel and sample; paper methods of the equation (a "
      "diagnostic, not comparable).\n");
  for (const std::string& w : warnings) std::printf("warning: %s\n", w.c_str());
  return all_usable ? kExitOk : kExitFail;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{
      "hrg-compare: run the paper's method (xi ignored), the paper's xi1 grid and maximum "
      "likelihood (all xi) on one session and print delta2, xi1, the relative deviation from the "
      "truth (sessions with \"simulation\"), the residual RMS and the time of each.\n"
      "Here 1: some estimate not usable; 4: bad command line or session.\n" +
      std::string(hrgbench::kExitCodesHelp)};
  std::string dir;
  bool quiet = false;
  cli.add_option("dir", dir, "session directory")->required();
  hrgbench::app::AddCommonFlags(cli, &quiet);
  return hrgbench::app::ParseAndRun(cli, argc, argv, "hrg-compare", quiet,
                                    [&] { return Run(dir); });
}
