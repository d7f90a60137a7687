#include "hrgbench/bench/tuning/tune_verdict.hpp"

#include <cmath>
#include <cstdio>

#include "hrgbench/analysis/gyro_units.hpp"

namespace hrgbench::bench {
namespace {

using analysis::kDegPerHourPerRadPerS;
using analysis::kDegPerSqrtHourPerRadPerSqrtS;

std::string Number(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.4g", v);
  return text;
}

// One check: `value` ± `std` against [lower, max] (lower = −max for a signed value, 0 for a
// magnitude: then the low side is the physical bound, unguarded).
TuneCheck Check(std::string name, double value, double std, double max, bool signed_value,
                const DecisionRule& rule, const std::string& unit) {
  TuneCheck check;
  check.name = std::move(name);
  check.value = value;
  check.std = std;
  check.max = max;
  const double lower = signed_value ? -max : 0.0;
  check.decision = Decide(value, std, lower, max, signed_value, rule,
                          check.name + " = " + Number(value) + " ± " + Number(std) + " " + unit,
                          "[" + Number(lower) + ", " + Number(max) + "] " + unit);
  return check;
}

TuneCheck NotEvaluated(std::string name, double max, std::string why) {
  TuneCheck check;
  check.name = std::move(name);
  check.value = std::nan("");
  check.std = std::nan("");
  check.max = max;
  check.decision.message = check.name + ": not evaluated, " + why;
  return check;
}

// The RMS over a turn that the harmonics' fit noise alone gives.
double NoiseRms(const analysis::RateErrorHarmonics& fit) {
  double sum = 0.0;
  for (std::size_t n = 0; n < fit.cos_std_rad_s.size(); ++n)
    sum +=
        fit.cos_std_rad_s[n] * fit.cos_std_rad_s[n] + fit.sin_std_rad_s[n] * fit.sin_std_rad_s[n];
  return std::sqrt(sum / 2.0);
}

}  // namespace

TuneVerdict JudgeTune(const TuneResult& result, const LimitsConfig& limits, bool stopped) {
  TuneVerdict verdict;
  if (stopped) {
    verdict.outcome = OutcomeKind::kAborted;
    verdict.reason = "stopped by the operator: " + result.why;
    return verdict;
  }
  if (result.verified.empty()) {
    verdict.outcome = OutcomeKind::kError;
    verdict.reason = result.why.empty() ? "the verification did not run" : result.why;
    return verdict;
  }
  if (!result.consistent) {
    verdict.outcome = OutcomeKind::kError;
    verdict.reason = "the after holds are not what the compensation's covariance predicts (chi2 " +
                     Number(result.chi2) + " on " + std::to_string(result.chi2_dof) +
                     " above its 0.999 quantile " + Number(result.chi2_limit) +
                     "): the rate error's model does not hold here, so no limit is judged";
    return verdict;
  }
  const TuneLimits& tune = limits.tune;
  const DecisionRule& rule = limits.decision;
  if (tune.rate_error_deg_h) {
    for (std::size_t i = 0; i < result.after.size() && i < result.verified.size(); ++i) {
      const double omega = result.verified[i].omega_rad_s;
      verdict.checks.push_back(
          Check("rate_error_deg_h at " + Number(omega) + " rad/s",
                result.after[i].fit.angle_dependent_rms_rad_s * kDegPerHourPerRadPerS,
                NoiseRms(result.after[i].fit) * kDegPerHourPerRadPerS, *tune.rate_error_deg_h,
                false, rule, "°/h"));
    }
  }
  const analysis::ScaleFactorFit& sf = result.scale_factor;
  if (tune.bias_deg_h) {
    verdict.checks.push_back(sf.ok ? Check("bias_deg_h", sf.bias_rad_s * kDegPerHourPerRadPerS,
                                           sf.bias_std_rad_s * kDegPerHourPerRadPerS,
                                           *tune.bias_deg_h, true, rule, "°/h")
                                   : NotEvaluated("bias_deg_h", *tune.bias_deg_h, sf.why));
  }
  if (tune.scale_factor_ppm) {
    verdict.checks.push_back(
        sf.ok ? Check("scale_factor_ppm", sf.scale_factor_error * 1e6,
                      sf.scale_factor_error_std * 1e6, *tune.scale_factor_ppm, true, rule, "ppm")
              : NotEvaluated("scale_factor_ppm", *tune.scale_factor_ppm, sf.why));
  }
  if (tune.scale_factor_asymmetry_ppm) {
    const double max = *tune.scale_factor_asymmetry_ppm;
    verdict.checks.push_back(
        !sf.ok ? NotEvaluated("scale_factor_asymmetry_ppm", max, sf.why)
        : !sf.asymmetry_known
            ? NotEvaluated("scale_factor_asymmetry_ppm", max,
                           "the asymmetry needs rates of both signs and two magnitudes "
                           "(hrg-bench tune --rates 0.3 -0.3 1 -1)")
            : Check("scale_factor_asymmetry_ppm", sf.asymmetry * 1e6, sf.asymmetry_std * 1e6, max,
                    true, rule, "ppm"));
  }
  const std::string no_hold = "there was no zero-rate hold (hrg-bench tune --zero-rate-hold S)";
  if (tune.arw_deg_per_sqrt_h) {
    const auto& z = result.stability;
    if (!z) {
      verdict.checks.push_back(
          NotEvaluated("arw_deg_per_sqrt_h", *tune.arw_deg_per_sqrt_h, no_hold));
    } else if (!z->arw_known) {
      verdict.checks.push_back(NotEvaluated("arw_deg_per_sqrt_h", *tune.arw_deg_per_sqrt_h,
                                            "the zero-rate hold is too short for a point at 1 s"));
    } else {
      verdict.checks.push_back(
          Check("arw_deg_per_sqrt_h", z->arw_rad_per_sqrt_s * kDegPerSqrtHourPerRadPerSqrtS,
                (z->arw_upper - z->arw_lower) / 2.0 * kDegPerSqrtHourPerRadPerSqrtS,
                *tune.arw_deg_per_sqrt_h, false, rule, "°/√h"));
    }
  }
  if (tune.bias_instability_deg_h) {
    const auto& z = result.stability;
    if (!z || z->allan.empty()) {
      verdict.checks.push_back(
          NotEvaluated("bias_instability_deg_h", *tune.bias_instability_deg_h, no_hold));
    } else {
      TuneCheck check = Check(
          "bias_instability_deg_h", z->bias_instability_rad_s * kDegPerHourPerRadPerS,
          (z->bias_instability_upper - z->bias_instability_lower) / 2.0 * kDegPerHourPerRadPerS,
          *tune.bias_instability_deg_h, false, rule, "°/h");
      if (!z->bias_instability_reached)
        check.decision.message += " (a bound: no floor within the hold)";
      verdict.checks.push_back(std::move(check));
    }
  }

  std::string missed, failed, not_evaluated;
  for (const VerifiedRate& v : result.verified)
    if (!v.met) missed += (missed.empty() ? "" : ", ") + Number(v.omega_rad_s) + " rad/s";
  for (const TuneCheck& c : verdict.checks) {
    if (c.decision.status == LimitStatus::kFail)
      failed += (failed.empty() ? "" : "; ") + c.decision.message;
    if (c.decision.status == LimitStatus::kNotEvaluated)
      not_evaluated += (not_evaluated.empty() ? "" : "; ") + c.decision.message;
  }
  if (!missed.empty() || !failed.empty()) {
    verdict.outcome = OutcomeKind::kFail;
    if (!missed.empty())
      verdict.reason = "the angle-dependent rate error did not fall " +
                       Number(limits.tune.min_improvement) + "x or to its predicted residual at " +
                       missed;
    if (!failed.empty()) verdict.reason += (verdict.reason.empty() ? "" : "; ") + failed;
    return verdict;
  }
  if (!not_evaluated.empty()) {
    verdict.outcome = OutcomeKind::kError;
    verdict.reason = not_evaluated;
    return verdict;
  }
  verdict.outcome = OutcomeKind::kPass;
  return verdict;
}

nlohmann::json TuneVerdictJson(const TuneVerdict& verdict) {
  nlohmann::json checks = nlohmann::json::array();
  const auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nullptr; };
  for (const TuneCheck& c : verdict.checks) {
    const Decision& d = c.decision;
    checks.push_back({{"name", c.name},
                      {"value", number(c.value)},
                      {"std", number(c.std)},
                      {"max", c.max},
                      {"status", ToString(d.status)},
                      {"zone", ToString(d.zone)},
                      {"expanded_uncertainty", number(d.expanded_uncertainty)},
                      {"retest", d.retest},
                      {"message", d.message}});
  }
  return {{"outcome", ToString(verdict.outcome)}, {"reason", verdict.reason}, {"checks", checks}};
}

}  // namespace hrgbench::bench
