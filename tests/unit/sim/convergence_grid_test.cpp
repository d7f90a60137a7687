// Long-run convergence of the default estimator on carrier-level data (issue 23, section 3): the
// production plan's 6 runs with a demodulation reference off the wave (±offset, alternating over
// the runs) and a common frequency drift (a temperature ramp of the resonator), over run lengths ×
// offsets × drifts. Every cell must converge, pass its fit checks and find every parameter within
// 5 reported std of the physical truth (mapped by the simulation). The information is there in
// every cell: the common phase costs two numbers per run, and δ, ξ are determined by the six rates
// at any of these lengths. The one thing the slow model lacks here (the ramp also scales the split,
// see the grid test) must be named by the fit where the data see it, never answered silently.
//
// Data: tests/support/convergence_grid.hpp, FastGridUnit (a 1 kHz carrier, 200 Hz output behind a
// 40 Hz filter, σ_y ≈ 1e-4, τ = 800 s, Δf = 20 mHz): the production chain's physics at a fifth of
// the rates, so that the grid runs in CI. benchmarks/convergence_grid_table.cpp prints the same
// grid at the production rates (docs/measurements/2026-11-26-convergence-grid.md).

#include "convergence_grid.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace hrgbench::testing {
namespace {

constexpr double kMaxErrorInStd = 5.0;

std::string Describe(const GridOutcome& out) {
  std::string text = std::string(out.converged ? "converged" : "NOT converged") +
                     (out.acceptable ? ", checks pass" : ", FLAGGED") + ", worst " +
                     GridParameterName(out.worst_parameter) + " " +
                     std::to_string(out.worst_error_in_std) + " std, tau " +
                     std::to_string(out.tau_s) + " s; drift per run (rad/s^2):";
  for (double q : out.drift_rad_s2) text += " " + std::to_string(q);
  if (!out.first_problem.empty()) text += "; " + out.first_problem;
  return text;
}

// The failure, reproduced: 6 × 100 s, ±0.06 rad/s, 0.5 mHz/s, the common phase started at
// zero (the estimator before its start from the data): not converged to the truth.
TEST(ConvergenceGridTest, ZeroCommonPhaseStartFailsOnLongRunsWithOffsetAndDrift) {
  const GridUnit unit = FastGridUnit();
  const double drift_mhz_s = 0.5;
  const auto runs = SimulateGridSession(unit, 100.0, 0.06, drift_mhz_s, 1000);
  const GridTruth truth = GridTruthFor(unit, drift_mhz_s, 100.0);
  estimator::MlOptions ml = GridFitOptions(unit);
  ml.common_phase_start_from_data = false;
  const GridOutcome zero_start =
      JudgeGridFit(estimator::EstimateMaximumLikelihood(runs, ml), truth);
  EXPECT_FALSE(zero_start.Good(kMaxErrorInStd)) << Describe(zero_start);

  const GridOutcome from_data =
      JudgeGridFit(estimator::EstimateMaximumLikelihood(runs, GridFitOptions(unit)), truth);
  EXPECT_TRUE(from_data.Good(kMaxErrorInStd)) << Describe(from_data);
  // Each run's fitted drift is the ramp's, 2π·0.5e-3 rad/s²: the sign was what went wrong.
  for (double drift : from_data.drift_rad_s2)
    EXPECT_NEAR(drift, 2.0 * std::numbers::pi * drift_mhz_s * 1e-3, 2e-5);
}

// The grid. Each (offset, drift) is simulated once at the longest length; the shorter sessions are
// its first seconds. Sparser than the table's (no 0.03 rad/s offset, which lies between 0 and
// 0.06 in every respect) to keep the test near 30 s on two loaded cores.
//
// Where the information runs out: a temperature ramp scales the whole stiffness, so the frequency
// split itself sweeps by α·Ṫ·T of its value during a run (2e-4 at 1 mHz/s over 200 s on this 1 kHz
// carrier; 5× less at 5 kHz). The slow model has one δ5, δ6 per session; on the longest runs with
// the largest ramps the residuals see the sweep (Ljung–Box z 8–35 on run 1, Ω = 0.1 rad/s, where
// the split dominates the wave's motion). There the fit must converge and say so (flagged), and
// its parameters still lie within 5 std of the split's sweep; nowhere may it be silently wrong.
TEST(ConvergenceGridTest, ConvergesEverywhereOnTheGrid) {
  const GridUnit unit = FastGridUnit();
  const std::vector<double> lengths_s = {10.0, 20.0, 50.0, 100.0, 200.0};
  const std::vector<double> offsets_rad_s = {0.0, 0.06, 0.1};
  const std::vector<double> drifts_mhz_s = {0.0, 0.1, 0.5, 1.0};
  int cells = 0, good = 0, flagged_where_expected = 0;
  for (double offset : offsets_rad_s) {
    for (double drift : drifts_mhz_s) {
      const auto full = SimulateGridSession(unit, lengths_s.back(), offset, drift, 2000);
      for (double length : lengths_s) {
        const auto runs = TruncateRuns(full, length, unit.output_rate_hz);
        const GridTruth truth = GridTruthFor(unit, drift, length);
        const GridOutcome out =
            JudgeGridFit(estimator::EstimateMaximumLikelihood(runs, GridFitOptions(unit)), truth);
        ++cells;
        const std::string where = "offset " + std::to_string(offset) + " rad/s, drift " +
                                  std::to_string(drift) + " mHz/s, " + std::to_string(length) +
                                  " s runs: " + Describe(out);
        const bool split_sweep_visible = drift >= 0.5 && length >= 200.0;
        if (out.Good(kMaxErrorInStd)) {
          ++good;
        } else if (split_sweep_visible && out.converged && !out.acceptable) {
          ++flagged_where_expected;
        } else {
          ADD_FAILURE() << where;
        }
        // Never a silent wrong answer, and converged everywhere.
        EXPECT_TRUE(out.converged) << where;
        EXPECT_FALSE(out.converged && out.acceptable && !out.Good(kMaxErrorInStd)) << where;
        EXPECT_LE(out.worst_error_in_std, kMaxErrorInStd) << where;
        // Each run's fitted drift is the ramp's (2π·drift rad/s², the same for every run).
        for (double fitted : out.drift_rad_s2)
          EXPECT_NEAR(fitted, 2.0 * std::numbers::pi * drift * 1e-3, 2e-5) << where;
      }
    }
  }
  EXPECT_EQ(good + flagged_where_expected, cells);
  EXPECT_GE(good, cells - 2 * static_cast<int>(offsets_rad_s.size()));
}

}  // namespace
}  // namespace hrgbench::testing
