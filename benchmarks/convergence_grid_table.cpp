// The long-run convergence grid of docs/estimator/convergence.md: for every run length × reference
// offset × common frequency drift, does the default estimator (EstimateMaximumLikelihood, the
// production options) converge to the truth on carrier-level data? A Markdown table.
//
// Design and data: tests/support/convergence_grid.hpp (the production plan's 6 runs on
// CarrierSimulation; the reference offset alternates in sign over the runs; the drift is a
// temperature ramp of the resonator). Each (offset, drift, seed) is simulated once at the longest
// length and the shorter sessions are its first seconds (the same releases, cut).
//
// A cell reads "ok e" when every seed's fit converged, passed its checks and put every parameter
// within 5 reported std of the truth (e: the worst |error|/std over the seeds); otherwise it says
// what went wrong in how many seeds: "flag" (a fit check failed), "nc" (not converged), "wrong"
// (converged, unflagged, a parameter beyond 5 std: a silent wrong answer).
//
// Usage: build/bin/convergence_grid_table [--unit production|fast] [--seeds 1]
//            [--lengths 10,20,50,100,200] [--offsets 0,0.03,0.06,0.1] [--drifts 0,0.1,0.5,1]
//            [--threads 0] [--verbose] [--zero-start] [--split-mhz 20]
// (--unit fast: a 1 kHz carrier at 200 Hz output, the unit test's chain; production: 5 kHz, 1 kHz;
// offsets in rad/s, drifts in mHz/s; --verbose prints every fit's outcome; --zero-start: each
// run's common phase started at zero, as the estimator did before docs/estimator/convergence.md.)

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <sstream>
#include <string>
#include <vector>

#include "convergence_grid.hpp"

namespace {

namespace grid = hrgbench::testing;
namespace est = hrgbench::estimator;

std::vector<double> ParseList(const char* text) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) out.push_back(std::atof(item.c_str()));
  return out;
}

struct Cell {
  int good = 0, flagged = 0, not_converged = 0, wrong = 0;
  double worst = 0.0;
  double seconds = 0.0;
  // Every usable fit's (δ, ξ) and reported std, for the scatter over seeds (--seeds ≥ 2).
  std::vector<Eigen::Matrix<double, 10, 1>> estimates, stds;
};

// Per parameter: the scatter of the estimates over the seeds against the mean reported std, and
// the mean error (against the release truth's interval) in reported std.
void PrintScatter(const Cell& cell, const grid::GridTruth& truth, const char* where) {
  const auto n = static_cast<int>(cell.estimates.size());
  if (n < 2) return;
  std::printf("%s, %d seeds: scatter / reported std (mean error / std):", where, n);
  for (int j = 0; j < 10; ++j) {
    double mean = 0.0, mean_std = 0.0;
    for (int i = 0; i < n; ++i) {
      mean += cell.estimates[i][j] / n;
      mean_std += cell.stds[i][j] / n;
    }
    double scatter = 0.0;
    for (int i = 0; i < n; ++i)
      scatter += (cell.estimates[i][j] - mean) * (cell.estimates[i][j] - mean);
    scatter = std::sqrt(scatter / (n - 1));
    const double centre = 0.5 * (truth.low[j] + truth.high[j]);
    std::printf(" %s %.2f (%+.2f)", grid::GridParameterName(j), scatter / mean_std,
                (mean - centre) / mean_std);
  }
  std::printf("; resolution ± %.2f\n", 1.0 / std::sqrt(2.0 * (n - 1)));
}

}  // namespace

int main(int argc, char** argv) {
  grid::GridUnit unit;
  std::string unit_name = "production";
  int seeds = 1;
  int threads = 0;
  bool verbose = false;
  double split_mhz = -1.0;  // --split-mhz: the unit's frequency split instead of its 20 mHz
  bool zero_start = false;  // --zero-start: the common phase started at zero (the estimator before)
  std::vector<double> lengths = {10, 20, 50, 100, 200};
  std::vector<double> offsets = {0, 0.03, 0.06, 0.1};
  std::vector<double> drifts = {0, 0.1, 0.5, 1};
  for (int i = 1; i < argc; ++i) {
    const bool has_value = i + 1 < argc;
    if (std::strcmp(argv[i], "--verbose") == 0) verbose = true;
    if (std::strcmp(argv[i], "--zero-start") == 0) zero_start = true;
    if (!has_value) continue;
    if (std::strcmp(argv[i], "--unit") == 0) unit_name = argv[i + 1];
    if (std::strcmp(argv[i], "--seeds") == 0) seeds = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--threads") == 0) threads = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--lengths") == 0) lengths = ParseList(argv[i + 1]);
    if (std::strcmp(argv[i], "--offsets") == 0) offsets = ParseList(argv[i + 1]);
    if (std::strcmp(argv[i], "--drifts") == 0) drifts = ParseList(argv[i + 1]);
    if (std::strcmp(argv[i], "--split-mhz") == 0) split_mhz = std::atof(argv[i + 1]);
  }
  if (unit_name == "fast") {
    unit = grid::FastGridUnit();
  } else if (unit_name != "production") {
    std::fprintf(stderr, "--unit must be production or fast\n");
    return 2;
  }
  if (split_mhz >= 0.0) unit.frequency_split_hz = 1e-3 * split_mhz;
  if (lengths.empty() || seeds < 1) return 2;
  const double longest = *std::max_element(lengths.begin(), lengths.end());
  constexpr double kMaxErrorInStd = 5.0;

  std::printf(
      "Convergence grid: unit %s (carrier %.0f Hz, output %.0f Hz, τ %.0f s, Δ(1/τ) %.1e 1/s, Δf "
      "%.0f mHz), 6 runs at ±0.1, ±0.3, ±1 rad/s, %d seed(s) per cell; common phase started %s; "
      "reference offset ± "
      "alternating over the runs; a cell is ok when every seed converged, passed its checks and "
      "is within %.0f std of the truth.\n\n",
      unit_name.c_str(), unit.carrier_hz, unit.output_rate_hz, unit.decay_time_s,
      unit.damping_split_per_s, 1e3 * unit.frequency_split_hz, seeds,
      zero_start ? "at zero" : "from the data", kMaxErrorInStd);
  std::vector<std::vector<Cell>> table(offsets.size() * drifts.size(),
                                       std::vector<Cell>(lengths.size()));
  int silent_wrong = 0, not_good = 0;
  for (std::size_t o = 0; o < offsets.size(); ++o) {
    for (std::size_t d = 0; d < drifts.size(); ++d) {
      for (int seed = 1; seed <= seeds; ++seed) {
        const std::vector<est::RunData> full = grid::SimulateGridSession(
            unit, longest, offsets[o], drifts[d], 1000u * static_cast<std::uint64_t>(seed));
        for (std::size_t l = 0; l < lengths.size(); ++l) {
          const auto runs = grid::TruncateRuns(full, lengths[l], unit.output_rate_hz);
          const auto start = std::chrono::steady_clock::now();
          const std::clock_t cpu_start = std::clock();
          est::MlOptions ml = grid::GridFitOptions(unit, threads);
          ml.common_phase_start_from_data = !zero_start;
          const est::EstimateSummary s = est::EstimateMaximumLikelihood(runs, ml);
          const double seconds =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          const double cpu_seconds = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
          const grid::GridOutcome out =
              grid::JudgeGridFit(s, grid::GridTruthFor(unit, drifts[d], lengths[l]));
          Cell& cell = table[o * drifts.size() + d][l];
          cell.seconds += seconds;
          if (s.IsUsable()) {
            Eigen::Matrix<double, 10, 1> e, sd;
            e << s.delta, s.xi;
            sd << s.delta_std, s.xi_std;
            cell.estimates.push_back(e);
            cell.stds.push_back(sd);
          }
          if (out.Good(kMaxErrorInStd)) {
            ++cell.good;
            cell.worst = std::max(cell.worst, out.worst_error_in_std);
          } else if (!out.converged) {
            ++cell.not_converged;
          } else if (!out.acceptable) {
            ++cell.flagged;
          } else {
            ++cell.wrong;
            ++silent_wrong;
          }
          if (!out.Good(kMaxErrorInStd)) ++not_good;
          if (verbose || !out.Good(kMaxErrorInStd)) {
            std::fprintf(stderr,
                         "offset %.3g drift %.3g length %.0f seed %d: %s, %s, worst %s %.2f std, "
                         "τ %.1f s, %d iterations, %.3f s (CPU %.3f s); drift per run",
                         offsets[o], drifts[d], lengths[l], seed, est::ToString(s.termination),
                         out.acceptable ? "checks pass" : "FLAGGED",
                         grid::GridParameterName(out.worst_parameter), out.worst_error_in_std,
                         out.tau_s, out.iterations, seconds, cpu_seconds);
            for (double q : out.drift_rad_s2) std::fprintf(stderr, " %.3g", q);
            std::fprintf(stderr, "%s%s\n", out.first_problem.empty() ? "" : "; ",
                         out.first_problem.c_str());
          }
        }
      }
    }
  }
  std::printf("| offset, rad/s | drift, mHz/s |");
  for (double length : lengths) std::printf(" %.0f s |", length);
  std::printf("\n|---:|---:|");
  for (std::size_t l = 0; l < lengths.size(); ++l) std::printf("---|");
  std::printf("\n");
  double total_seconds = 0.0;
  for (std::size_t o = 0; o < offsets.size(); ++o) {
    for (std::size_t d = 0; d < drifts.size(); ++d) {
      std::printf("| %.3g | %.3g |", offsets[o], drifts[d]);
      for (std::size_t l = 0; l < lengths.size(); ++l) {
        const Cell& cell = table[o * drifts.size() + d][l];
        total_seconds += cell.seconds;
        if (cell.good == seeds) {
          std::printf(" ok %.1f |", cell.worst);
          continue;
        }
        std::string text;
        if (cell.flagged) text += std::to_string(cell.flagged) + " flag ";
        if (cell.not_converged) text += std::to_string(cell.not_converged) + " nc ";
        if (cell.wrong) text += std::to_string(cell.wrong) + " WRONG ";
        std::printf(" %s|", text.c_str());
      }
      std::printf("\n");
    }
  }
  if (seeds >= 2) {
    std::printf("\n");
    for (std::size_t o = 0; o < offsets.size(); ++o)
      for (std::size_t d = 0; d < drifts.size(); ++d)
        for (std::size_t l = 0; l < lengths.size(); ++l) {
          char where[160];
          std::snprintf(where, sizeof where, "offset %.3g, drift %.3g, %.0f s", offsets[o],
                        drifts[d], lengths[l]);
          PrintScatter(table[o * drifts.size() + d][l],
                       grid::GridTruthFor(unit, drifts[d], lengths[l]), where);
        }
  }
  std::printf(
      "\n%d fit(s) not ok, %d of them silently wrong (converged, unflagged, beyond %.0f std); "
      "fits took %.1f s in all.\n",
      not_good, silent_wrong, kMaxErrorInStd, total_seconds);
  return 0;
}
