// Tuning one unit: estimate → p → written → refined on the table → written → verified.

#include "hrgbench/bench/tuning/tune_unit.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "hrgbench/analysis/allan_deviation.hpp"

namespace hrgbench::bench {
namespace {

void Log(const std::function<void(std::string_view)>& on_log, const std::string& line) {
  if (on_log) on_log(line);
}

std::string Rate(double rad_s) {
  std::ostringstream out;
  out.precision(4);
  out << rad_s << " rad/s";
  return out.str();
}

// Holds at every rate of the plan, `turns` each; false (and result.why) at the first failure.
bool HoldAtEveryRate(const BenchHardware& hardware, const UnitHardware& unit, const TunePlan& plan,
                     double turns, double angular_gain, double earth_rate_rad_s,
                     const std::atomic<int>* stop, const char* role,
                     std::vector<OperatingHold>& holds, TuneResult& result,
                     const std::function<void(std::string_view)>& on_log) {
  for (const double omega : plan.rates_rad_s) {
    OperatingHoldPlan hold_plan = plan.hold;
    hold_plan.omega_rad_s = omega;
    hold_plan.turns = turns;
    hold_plan.duration_s = 0.0;
    hold_plan.angular_gain = angular_gain;
    OperatingHold hold = RunOperatingHold(hardware, unit, hold_plan, earth_rate_rad_s, stop);
    if (!hold.ok) {
      result.why = std::string(role) + " hold at " + Rate(omega) + ": " + hold.why;
      return false;
    }
    Log(on_log, std::string(role) + " hold at " + Rate(omega) + ": " +
                    std::to_string(hold.samples) + " samples, angle-dependent rate error " +
                    Rate(hold.fit.angle_dependent_rms_rad_s) + ", bias " +
                    Rate(hold.fit.bias_rad_s));
    holds.push_back(std::move(hold));
  }
  return true;
}

estimator::VerificationHold AsVerification(const OperatingHold& hold) {
  const analysis::RateErrorHarmonics& f = hold.fit;
  return {hold.omega_rad_s,
          f.bias_rad_s,
          std::hypot(f.bias_std_rad_s, hold.omega_std_error_rad_s),
          f.cos_rad_s[0],
          f.cos_std_rad_s[0],
          f.sin_rad_s[0],
          f.sin_std_rad_s[0]};
}

ZeroRateStability ZeroRateStabilityOf(const std::vector<double>& rate_error_rad_s,
                                      double sample_period_s) {
  ZeroRateStability z;
  double sum = 0.0;
  for (const double e : rate_error_rad_s) sum += e;
  z.bias_rad_s =
      rate_error_rad_s.empty() ? 0.0 : sum / static_cast<double>(rate_error_rad_s.size());
  // The octaves, and τ = 1 s itself (where N is read) when the hold is long enough for it.
  std::vector<int> factors = analysis::OctaveFactors(rate_error_rad_s.size());
  const int one_second = static_cast<int>(std::lround(1.0 / sample_period_s));
  if (!factors.empty() && one_second < factors.back() &&
      std::find(factors.begin(), factors.end(), one_second) == factors.end()) {
    factors.insert(std::upper_bound(factors.begin(), factors.end(), one_second), one_second);
  }
  z.allan = analysis::OverlappingAllanDeviation(rate_error_rad_s, sample_period_s, factors);
  bool first = true;
  for (const analysis::AllanPoint& p : z.allan) {
    if (p.m == one_second) {
      z.arw_known = true;
      z.arw_rad_per_sqrt_s = p.deviation;
      z.arw_lower = p.lower;
      z.arw_upper = p.upper;
    }
    if (first || p.deviation < z.bias_instability_rad_s * 0.664) {
      first = false;
      z.bias_instability_rad_s = p.deviation / 0.664;
      z.bias_instability_lower = p.lower / 0.664;
      z.bias_instability_upper = p.upper / 0.664;
      z.bias_instability_tau_s = p.tau_s;
    }
  }
  // A floor is where σ stops falling: at the longest τ the curve may still be falling, and the
  // minimum is then a bound on B, not B.
  z.bias_instability_reached = !z.allan.empty() && z.bias_instability_tau_s < z.allan.back().tau_s;
  return z;
}

}  // namespace

std::optional<std::string> TunePlanProblem(const TunePlan& plan) {
  const auto& rates = plan.rates_rad_s;
  const bool plus = std::any_of(rates.begin(), rates.end(), [](double w) { return w > 0.0; });
  const bool minus = std::any_of(rates.begin(), rates.end(), [](double w) { return w < 0.0; });
  if (plus && minus) return std::nullopt;
  return "the verification needs rates of both signs (the refinement separates what scales with "
         "the rate from what does not)";
}

hw::CompensationValues ToCompensationValues(const estimator::CompensationSet& p) {
  hw::CompensationValues values{};
  Eigen::Map<estimator::CompensationVector>(values.data()) = p.AsVector();
  return values;
}

TuneResult TuneUnit(const BenchHardware& hardware, const UnitHardware& unit,
                    const estimator::CompensationSet& from_estimate, const TunePlan& plan,
                    double earth_rate_rad_s, const std::atomic<int>* stop,
                    const std::function<void(std::string_view)>& on_log) {
  TuneResult result;
  result.from_estimate = from_estimate;
  const auto fail = [&](std::string why) {
    if (hardware.table != nullptr) hardware.table->SafeStop();
    if (unit.gyro != nullptr) (void)unit.gyro->Stop();
    result.ok = false;
    if (result.why.empty()) result.why = std::move(why);
    Log(on_log, "tuning stopped: " + result.why + "; the electronics hold the block " +
                    result.block_at_end);
    return result;
  };
  // Refused before anything is commanded.
  const auto refuse = [&](std::string why) {
    result.why = std::move(why);
    Log(on_log, "tuning refused: " + result.why);
    return result;
  };
  if (unit.operating == nullptr || unit.gyro == nullptr || hardware.table == nullptr)
    return refuse("the station gives no operating-mode access to this unit's electronics");
  if (auto problem = TunePlanProblem(plan)) return refuse(*problem);
  if (!(from_estimate.delta[estimator::kScaleFactor] != 0.0))
    return refuse("p from the estimate has no angular gain");
  hw::OperatingGyro& operating = *unit.operating;

  // 1. What the electronics hold.
  if (auto held = operating.ReadParameters(); held) {
    result.held_before = *held;
  } else {
    result.held_before_problem = held.error().ToString();
  }
  Log(on_log, result.held_before
                  ? "the electronics' block read"
                  : "the electronics hold no readable block: " + result.held_before_problem);
  const double held_gain =
      result.held_before ? (*result.held_before)[estimator::kScaleFactor] : 0.0;

  // 2. Before.
  if (result.held_before && held_gain != 0.0) {
    if (!HoldAtEveryRate(hardware, unit, plan, plan.verify_turns, held_gain, earth_rate_rad_s, stop,
                         "before", result.before, result, on_log)) {
      return fail(result.why);
    }
  }

  // 3. p from the estimate.
  const auto write = [&](const estimator::CompensationSet& p,
                         const char* name) -> std::optional<hw::CompensationWrite> {
    auto written = operating.WriteParameters(ToCompensationValues(p));
    if (!written) {
      result.why = std::string("writing the block ") + name + ": " + written.error().ToString();
      // A failed commit leaves whichever block the electronics then hold (the message names it).
      if (written.error().code != hw::GyroErrorCode::kReadBackMismatch &&
          written.error().code != hw::GyroErrorCode::kInvalidState)
        result.block_at_end = "unknown";
      return std::nullopt;
    }
    result.block_at_end = name;
    Log(on_log, std::string("block ") + name + " written, read back, committed (generation " +
                    std::to_string(written->generation) + ")");
    return *written;
  };
  result.first_write = write(from_estimate, "from the estimate");
  if (!result.first_write) return fail(result.why);

  // 4. Refine.
  const double gain = from_estimate.delta[estimator::kScaleFactor];
  if (!HoldAtEveryRate(hardware, unit, plan, plan.refine_turns, gain, earth_rate_rad_s, stop,
                       "refine", result.refine, result, on_log)) {
    return fail(result.why);
  }
  std::vector<estimator::VerificationHold> holds;
  for (const OperatingHold& hold : result.refine) holds.push_back(AsVerification(hold));
  if (!estimator::RefineCompensation(from_estimate, holds, &result.refinement))
    return fail("the refinement holds cannot be combined (two distinct rates, finite std)");
  result.final_write = write(result.refinement.refined, "refined");
  if (!result.final_write) return fail(result.why);

  // 5. After, beside the prediction.
  const estimator::CompensationSet& tuned = result.refinement.refined;
  if (!HoldAtEveryRate(hardware, unit, plan, plan.verify_turns,
                       tuned.delta[estimator::kScaleFactor], earth_rate_rad_s, stop, "after",
                       result.after, result, on_log)) {
    return fail(result.why);
  }
  if (plan.zero_rate_hold_s > 0.0) {
    OperatingHoldPlan zero = plan.hold;
    zero.omega_rad_s = 0.0;
    zero.duration_s = plan.zero_rate_hold_s;
    zero.harmonics = 0;
    OperatingHold hold = RunOperatingHold(hardware, unit, zero, earth_rate_rad_s, stop);
    if (!hold.ok) return fail("zero-rate hold: " + hold.why);
    result.stability = ZeroRateStabilityOf(hold.rate_error_rad_s, 1.0 / plan.hold.sample_rate_hz);
    Log(on_log, "zero-rate hold: " + std::to_string(hold.samples) + " samples");
    result.zero_rate = std::move(hold);
  }
  if (auto stopped = hardware.table->Stop(); !stopped) return fail(stopped.error().ToString());

  result.ok = true;
  std::string missed;
  std::vector<analysis::RateHoldMean> means;  // the mean rate errors, for the scale factor
  for (std::size_t i = 0; i < result.after.size(); ++i) {
    const OperatingHold& after = result.after[i];
    const analysis::RateErrorHarmonics& f = after.fit;
    VerifiedRate v;
    v.omega_rad_s = after.omega_rad_s;
    v.after_rms_rad_s = f.angle_dependent_rms_rad_s;
    const Eigen::Matrix3d predicted =
        estimator::PredictedRateErrorCovariance(tuned, after.omega_rad_s);
    const estimator::VerificationHold m = AsVerification(after);
    means.push_back({after.omega_rad_s, m.bias_rad_s, m.bias_std_rad_s});
    Eigen::Matrix3d total = predicted;
    total(0, 0) += m.bias_std_rad_s * m.bias_std_rad_s;
    total(1, 1) += m.cos_std_rad_s * m.cos_std_rad_s;
    total(2, 2) += m.sin_std_rad_s * m.sin_std_rad_s;
    const Eigen::Vector3d r(m.bias_rad_s, m.cos_rad_s, m.sin_rad_s);
    v.chi2 = r.dot(total.ldlt().solve(r));
    double higher = 0.0;  // the fit's noise in the harmonics above the first
    for (std::size_t n = 1; n < f.cos_std_rad_s.size(); ++n)
      higher += f.cos_std_rad_s[n] * f.cos_std_rad_s[n] + f.sin_std_rad_s[n] * f.sin_std_rad_s[n];
    v.predicted_rms_rad_s = std::sqrt((total(1, 1) + total(2, 2) + higher) / 2.0);
    if (i < result.before.size()) {
      v.before_rms_rad_s = result.before[i].fit.angle_dependent_rms_rad_s;
      v.met = v.after_rms_rad_s <= std::max(v.before_rms_rad_s / plan.min_improvement,
                                            plan.predicted_sigmas * v.predicted_rms_rad_s);
    } else {
      // No block before to compare with: the bound is the prediction alone.
      v.met = v.after_rms_rad_s <= plan.predicted_sigmas * v.predicted_rms_rad_s;
    }
    if (!v.met) missed += (missed.empty() ? "" : ", ") + Rate(v.omega_rad_s);
    result.chi2 += v.chi2;
    result.chi2_dof += 3;
    result.verified.push_back(v);
  }
  result.scale_factor = analysis::FitScaleFactor(means);
  result.chi2_limit = analysis::ChiSquaredQuantile(plan.consistency_probability, result.chi2_dof);
  result.consistent = result.chi2 <= result.chi2_limit;
  if (!missed.empty()) {
    result.ok = false;
    result.why = "the rate error did not fall to its bound at " + missed;
  }

  // Worse than before at some rate: the block held before goes back.
  bool worse = false;
  for (const VerifiedRate& v : result.verified)
    worse = worse || (v.before_rms_rad_s > 0.0 && v.after_rms_rad_s >= v.before_rms_rad_s);
  if (worse && result.held_before) {
    if (auto restored = operating.WriteParameters(*result.held_before); restored) {
      result.restored = true;
      result.block_at_end = "restored";
    } else {
      result.why += "; restoring the block held before failed: " + restored.error().ToString();
    }
  }
  Log(on_log, std::string(result.ok ? "tuned" : "not tuned: " + result.why) +
                  "; the electronics hold the block " + result.block_at_end);
  return result;
}

namespace {

nlohmann::json ValuesJson(const hw::CompensationValues& v) {
  return nlohmann::json{{"delta", std::vector<double>(v.begin(), v.begin() + 6)},
                        {"xi", std::vector<double>(v.begin() + 6, v.begin() + 10)},
                        {"rate_bias_rad_s", v[10]}};
}

nlohmann::json SetJson(const estimator::CompensationSet& p) {
  nlohmann::json j = ValuesJson(ToCompensationValues(p));
  j["estimated"] = std::vector<bool>(p.estimated.begin(), p.estimated.end());
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < estimator::kCompensationSize; ++i) {
    std::vector<double> row(estimator::kCompensationSize);
    for (int k = 0; k < estimator::kCompensationSize; ++k)
      row[static_cast<std::size_t>(k)] = p.covariance(i, k);
    rows.push_back(row);
  }
  j["covariance"] = rows;
  return j;
}

nlohmann::json Finite(double v) { return std::isfinite(v) ? nlohmann::json(v) : nullptr; }

nlohmann::json HoldJson(const OperatingHold& h) {
  const analysis::RateErrorHarmonics& f = h.fit;
  return {{"omega_set_rad_s", h.omega_set_rad_s},
          {"omega_rad_s", h.omega_rad_s},
          {"omega_std_error_rad_s", h.omega_std_error_rad_s},
          {"omega_source", h.omega_source},
          {"duration_s", h.duration_s},
          {"samples", h.samples},
          {"sequence_gaps", h.sequence_gaps},
          {"bias_rad_s", f.bias_rad_s},
          {"bias_std_rad_s", f.bias_std_rad_s},
          {"cos_rad_s", f.cos_rad_s},
          {"cos_std_rad_s", f.cos_std_rad_s},
          {"sin_rad_s", f.sin_rad_s},
          {"sin_std_rad_s", f.sin_std_rad_s},
          {"angle_dependent_rms_rad_s", f.angle_dependent_rms_rad_s},
          {"angle_span_rad", f.angle_span_rad},
          {"loops",
           {{"reports", h.loops.reports},
            {"incomplete", h.loops.incomplete},
            {"max_abs_energy_error", h.loops.max_abs_energy_error},
            {"max_abs_quadrature_ratio", h.loops.max_abs_quadrature_ratio},
            {"energy_error_mean", Finite(h.loops.Mean(0))},
            {"energy_error_rms", Finite(h.loops.Rms(0))},
            {"quadrature_ratio_mean", Finite(h.loops.Mean(1))},
            {"quadrature_ratio_rms", Finite(h.loops.Rms(1))},
            {"amplitude_effort_mean_per_s", Finite(h.loops.Mean(2))},
            {"quadrature_effort_rms_rad_s", Finite(h.loops.Rms(3))}}}};
}

nlohmann::json HoldsJson(const std::vector<OperatingHold>& holds) {
  nlohmann::json j = nlohmann::json::array();
  for (const OperatingHold& h : holds) j.push_back(HoldJson(h));
  return j;
}

nlohmann::json WriteJson(const std::optional<hw::CompensationWrite>& w) {
  if (!w) return nullptr;
  return {{"generation", w->generation},
          {"previous", w->previous ? ValuesJson(*w->previous) : nlohmann::json(nullptr)}};
}

}  // namespace

nlohmann::json TuneResultJson(const TuneResult& r) {
  nlohmann::json j;
  j["ok"] = r.ok;
  j["why"] = r.why;
  j["held_before"] = r.held_before ? ValuesJson(*r.held_before) : nlohmann::json(nullptr);
  if (!r.held_before_problem.empty()) j["held_before_problem"] = r.held_before_problem;
  j["from_estimate"] = SetJson(r.from_estimate);
  j["first_write"] = WriteJson(r.first_write);
  if (r.final_write) {
    j["refined"] = SetJson(r.refinement.refined);
    j["slope_check"] = {{"d_xi1", r.refinement.slope_check[0]},
                        {"d_xi4", r.refinement.slope_check[1]},
                        {"scale_factor_error", r.refinement.slope_check[2]},
                        {"std", std::vector<double>(r.refinement.slope_check_std.data(),
                                                    r.refinement.slope_check_std.data() + 3)}};
  }
  j["final_write"] = WriteJson(r.final_write);
  j["restored"] = r.restored;
  j["block_at_end"] = r.block_at_end;
  j["holds"] = {{"before", HoldsJson(r.before)},
                {"refine", HoldsJson(r.refine)},
                {"after", HoldsJson(r.after)}};
  nlohmann::json verified = nlohmann::json::array();
  for (const VerifiedRate& v : r.verified) {
    verified.push_back({{"omega_rad_s", v.omega_rad_s},
                        {"before_rms_rad_s", v.before_rms_rad_s},
                        {"after_rms_rad_s", v.after_rms_rad_s},
                        {"predicted_rms_rad_s", v.predicted_rms_rad_s},
                        {"chi2", v.chi2},
                        {"met", v.met}});
  }
  const analysis::ScaleFactorFit& sf = r.scale_factor;
  j["scale_factor"] =
      sf.ok
          ? nlohmann::json{{"bias_rad_s", sf.bias_rad_s},
                           {"bias_std_rad_s", sf.bias_std_rad_s},
                           {"error_ppm", sf.scale_factor_error * 1e6},
                           {"error_std_ppm", sf.scale_factor_error_std * 1e6},
                           {"nonlinearity_ppm", sf.nonlinearity_known
                                                    ? nlohmann::json(sf.nonlinearity * 1e6)
                                                    : nlohmann::json(nullptr)},
                           {"asymmetry_ppm", sf.asymmetry_known ? nlohmann::json(sf.asymmetry * 1e6)
                                                                : nlohmann::json(nullptr)},
                           {"asymmetry_std_ppm", sf.asymmetry_known
                                                     ? nlohmann::json(sf.asymmetry_std * 1e6)
                                                     : nlohmann::json(nullptr)},
                           {"chi2", sf.chi2},
                           {"dof", sf.dof}}
          : nlohmann::json(nullptr);
  if (r.stability) {
    const ZeroRateStability& z = *r.stability;
    nlohmann::json points = nlohmann::json::array();
    for (const analysis::AllanPoint& p : z.allan)
      points.push_back({{"tau_s", p.tau_s},
                        {"deviation_rad_s", p.deviation},
                        {"lower_rad_s", p.lower},
                        {"upper_rad_s", p.upper},
                        {"edf", p.edf}});
    j["zero_rate"] = {
        {"hold", HoldJson(*r.zero_rate)},
        {"bias_rad_s", z.bias_rad_s},
        {"allan", points},
        {"arw_rad_per_sqrt_s",
         z.arw_known ? nlohmann::json(z.arw_rad_per_sqrt_s) : nlohmann::json(nullptr)},
        {"arw_interval", {z.arw_lower, z.arw_upper}},
        {"bias_instability_rad_s", z.bias_instability_rad_s},
        {"bias_instability_interval", {z.bias_instability_lower, z.bias_instability_upper}},
        {"bias_instability_tau_s", z.bias_instability_tau_s},
        {"bias_instability_reached", z.bias_instability_reached}};
  }
  j["verification"] = {{"rates", verified},
                       {"chi2", r.chi2},
                       {"chi2_dof", r.chi2_dof},
                       {"chi2_limit", r.chi2_limit},
                       {"consistent", r.consistent}};
  return j;
}

}  // namespace hrgbench::bench
