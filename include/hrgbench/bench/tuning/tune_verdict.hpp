#pragma once
// The tuning's verdict: a TuneResult judged against the limits file's [tune] (config
// limits_config.hpp TuneLimits) under the file's decision rule (analysis/decision.hpp), in the
// field's units (°/h, ppm, °/√h):
//
//   ABORTED  the tuning was stopped (Ctrl-C)
//   ERROR    a step did not run to its end (a hold, a write, the table: the bench's), or the after
//            holds are not what p's covariance predicts (χ² beyond its 0.999 quantile: the model
//            of the rate error does not hold, so no limit is trusted: never a PASS), or a declared
//            limit could not be judged (NOT EVALUATED: e.g. an ARW limit without a zero-rate hold)
//   FAIL     a rate whose angle-dependent error did not fall to its bound (min_improvement, or the
//            prediction), or a declared limit not met (non-conforming, or undecided within its
//            guard band: retest)
//   PASS     every step ran, the residuals are the predicted ones, every rate met its bound and
//            every declared limit was judged with its uncertainty and met.
//
// The values judged and their standard uncertainties:
//   rate_error_deg_h  per rate, the after hold's RMS over a turn of its harmonics; u the RMS the
//                     fit's noise alone gives (√(Σ(σc² + σs²)/2)), conservative near zero
//   bias_deg_h        the scale-factor line's intercept and its std (analysis/scale_factor.hpp)
//   scale_factor_ppm  its slope and its std
//   arw_deg_per_sqrt_h, bias_instability_deg_h   the zero-rate hold's, u half its 68.3 % interval
//                     (a bias instability whose floor the hold did not reach is judged as the
//                     bound it is)
// Pure; allocates.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hrgbench/analysis/decision.hpp"
#include "hrgbench/bench/tuning/tune_unit.hpp"
#include "hrgbench/config/limits_config.hpp"
#include "hrgbench/session/session_outcome.hpp"

namespace hrgbench::bench {

struct TuneCheck {
  std::string name;  // the [tune] key ("rate_error_deg_h"), with the rate for a per-rate check
  double value = 0.0;
  double std = 0.0;
  double max = 0.0;
  Decision decision;
};

struct TuneVerdict {
  OutcomeKind outcome = OutcomeKind::kError;
  std::string reason;  // what decided it ("" for a PASS)
  std::vector<TuneCheck> checks;
};

// `stopped`: the tuning ended on a stop request.
TuneVerdict JudgeTune(const TuneResult& result, const LimitsConfig& limits, bool stopped);

nlohmann::json TuneVerdictJson(const TuneVerdict& verdict);

}  // namespace hrgbench::bench
