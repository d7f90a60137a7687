#pragma once
// Which of the plan's remaining runs a unit still measuring needs most (issue 27 §1, the sequence's
// [adaptive] next_run = "most_informative").
//
// What keeps an adaptive session going is a limit still undecided: its value inside the guard band,
// its uncertainty u too large for the distance to the edge. A run shrinks u as much as it adds
// information about that quantity, and different runs inform different quantities: the Bryan
// factor (δ2) is learnt from the pattern's precession, in proportion to Ω²; the damping split from
// the wave's angle to the damping axes; the pick-off errors from the wave states. So after each
// run, for each candidate, the Cramér–Rao bound (estimator/cramer_rao.hpp) of the runs made with
// and without it, at the estimate and its noise: each undecided limit's u from both (its
// quantity's statistical part, mapped as the record maps it: analysis/engineering_of_record.hpp),
// and the candidate's score is its relative information for the undecided limits per second of
// table time, Σ (u_without² / u_with² − 1) / table_s. The bound is evaluated at 20 samples/s with
// the noise scaled to keep the information per second (the demodulated channels move far slower
// than that), so a ranking costs a few tens of milliseconds.

#include <span>
#include <vector>

#include "hrgbench/analysis/verdict.hpp"
#include "hrgbench/estimator/run_data.hpp"
#include "hrgbench/estimator/summary.hpp"
#include "hrgbench/session/session_record.hpp"

namespace hrgbench::bench {

struct NextRunCandidate {
  int id = 0;
  estimator::RunPlan plan;  // in the unit's frame (the record's plan), its length and rate
  double table_s = 0.0;     // what it costs the table: its free run, settling and excitation; > 0
};

// One score per candidate (above; ≥ 0), or empty when no limit is undecided or the bound cannot be
// had (an unusable estimate, a δ held, no noise level, a bound that fails). `made`: the unit's
// complete runs.
std::vector<double> NextRunScores(const estimator::EstimateSummary& estimate,
                                  const Verdict& verdict, const session::SessionRecord& record,
                                  std::span<const estimator::RunPlan> made,
                                  std::span<const NextRunCandidate> candidates);

}  // namespace hrgbench::bench
