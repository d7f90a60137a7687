#pragma once
// Tuning one unit (issue 28 §2–§4): its estimate made into the compensation p, written to its
// electronics, refined on the table, written again, and verified as the paper's quality criterion,
// the rate error Ω̂ − Ω at constant rates of both signs:
//
//   1. the block the electronics hold, read (kept so it can be restored);
//   2. "before": a verification hold at each rate with that block;
//   3. p from the estimate written (staged, read back, committed, read back);
//   4. "refine": holds at each rate read with p; what free runs cannot see (the operating mode's
//      drift and bias, the forcers' errors) from them (estimator::RefineCompensation); written;
//   5. "after": a verification hold at each rate with the refined p, each beside the residual the
//      refined p's covariance predicts (J·Σ·Jᵀ plus the hold's own fit and Ω uncertainty);
//   6. the after holds' mean errors over Ω as a bias and a scale-factor error (and, asked for, a
//      zero-rate hold's Allan deviation: angle random walk and bias instability);
//   7. the table to zero.
//
// On a failure after a write the electronics keep the block last committed (a valid one, named in
// the result); when the verification finds the rate error not lower than before, the block held
// before is restored and the result says so. On every path the table is stopped and the gyro left
// stopped. Units: SI (rad/s) as in operating_hold.hpp.

#include <atomic>
#include <cstddef>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hrgbench/analysis/allan_deviation.hpp"
#include "hrgbench/analysis/scale_factor.hpp"
#include "hrgbench/bench/sequencer/sequencer.hpp"
#include "hrgbench/bench/tuning/operating_hold.hpp"
#include "hrgbench/estimator/compensation.hpp"
#include "hrgbench/hw/operating_gyro.hpp"

namespace hrgbench::bench {

// p as the electronics' block holds it (estimator/compensation.hpp's vector order; back:
// estimator::CompensationFromVector).
hw::CompensationValues ToCompensationValues(const estimator::CompensationSet& p);

struct TunePlan {
  // The verification's rates in the unit's frame (without the Earth rate): at least two distinct
  // ones, both signs (the refinement separates what scales with Ω from what does not).
  std::vector<double> rates_rad_s = {0.3, -0.3};
  double verify_turns = 2.0;  // turns of 2θ per "before" and "after" hold
  double refine_turns = 8.0;  // per "refine" hold: its intercepts become p's drift and bias
  OperatingHoldPlan hold;     // sample rate, wave, fit window, table criteria (rate, turns: above)
  // The angle-dependent rate error must fall by this factor at every rate, or to within what the
  // estimate's uncertainty predicts (`predicted_sigmas` × its std), whichever is larger (issue 28).
  double min_improvement = 100.0;
  double predicted_sigmas = 3.0;
  // The "after" residual against its prediction: χ² over the holds' (b, c, s) below this
  // quantile of χ²(3·holds) is "consistent".
  double consistency_probability = 0.999;
  // > 0: a hold of this long at zero table rate after the verification, with the tuned block: the
  // overlapping Allan deviation of its rate output (IEEE 952; analysis/allan_deviation.hpp).
  double zero_rate_hold_s = 0.0;
};

// The zero-rate hold's stability: the Allan deviation at octave τ with its 68.3 % interval (white
// rate noise's degrees of freedom), and the two figures read off it (IEEE 952 Annex C): the angle
// random walk N = σ(τ = 1 s) and the bias instability B = min σ / 0.664, each with the interval of
// the point it is read at.
struct ZeroRateStability {
  std::vector<analysis::AllanPoint> allan;
  double bias_rad_s = 0.0;  // the hold's mean rate error
  bool arw_known = false;   // a point at τ = 1 s
  double arw_rad_per_sqrt_s = 0.0, arw_lower = 0.0, arw_upper = 0.0;
  double bias_instability_rad_s = 0.0, bias_instability_lower = 0.0, bias_instability_upper = 0.0;
  double bias_instability_tau_s = 0.0;  // where the minimum is
  // The minimum is a floor (σ rises again after it); false: σ still falls at the longest τ the
  // hold allows, and B is only bounded by the value above.
  bool bias_instability_reached = false;
};

// Why a plan cannot be run (nothing is commanded then), or nullopt: the rates must have both
// signs.
std::optional<std::string> TunePlanProblem(const TunePlan& plan);

// One "after" hold beside its prediction.
struct VerifiedRate {
  double omega_rad_s = 0.0;
  double before_rms_rad_s = 0.0;  // the angle-dependent rate error's RMS over a turn, before
  double after_rms_rad_s = 0.0;   // and after
  // What the refined p's covariance predicts for the after hold's RMS (its 1-σ, from J·Σ·Jᵀ and
  // the hold's fit std), rad/s.
  double predicted_rms_rad_s = 0.0;
  double chi2 = 0.0;  // (b, c, s) against (0, 0, 0) with the predicted + measured covariance
  bool met = false;   // after ≤ max(before / min_improvement, predicted_sigmas × predicted)
};

struct TuneResult {
  bool ok = false;  // every step ran and every rate met its bound
  std::string why;  // when not ok: the first failure or the rates that missed
  std::optional<hw::CompensationValues> held_before;  // nullopt: none valid or not readable
  std::string held_before_problem;
  estimator::CompensationSet from_estimate;
  std::optional<hw::CompensationWrite> first_write;
  estimator::CompensationRefinement refinement;
  std::optional<hw::CompensationWrite> final_write;
  bool restored = false;  // the block held before was made active again
  std::vector<OperatingHold> before, refine, after;
  std::vector<VerifiedRate> verified;
  // The after holds' mean rate errors over Ω: bias, scale-factor error, nonlinearity.
  analysis::ScaleFactorFit scale_factor;
  std::optional<OperatingHold> zero_rate;  // when the plan asks for one
  std::optional<ZeroRateStability> stability;
  double chi2 = 0.0;  // summed over the after holds
  int chi2_dof = 0;
  double chi2_limit = 0.0;
  bool consistent = false;
  // The block the electronics hold at the end: "held before", "from the estimate", "refined",
  // "restored", or "unknown" (a write whose commit was not confirmed).
  std::string block_at_end = "held before";
};

// `unit` of `hardware`; `from_estimate`: p from the session's estimate
// (estimator::CompensationFromEstimate). `earth_rate_rad_s` on the table's axis. `on_log`: one
// line per step (may be empty). `stop`: a stop request ends the tuning at its next check.
TuneResult TuneUnit(const BenchHardware& hardware, const UnitHardware& unit,
                    const estimator::CompensationSet& from_estimate, const TunePlan& plan,
                    double earth_rate_rad_s, const std::atomic<int>* stop = nullptr,
                    const std::function<void(std::string_view)>& on_log = {});

// The result as the record keeps it (tune.json): the blocks, p and its covariance, every hold's
// rate, Ω and fit, the verification; SI units, named.
nlohmann::json TuneResultJson(const TuneResult& result);

}  // namespace hrgbench::bench
