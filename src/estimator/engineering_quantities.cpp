#include "hrgbench/estimator/engineering_quantities.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <utility>

#include "hrgbench/estimator/physical_parameters.hpp"
#include "hrgbench/estimator/pickoff_frame.hpp"
#include "hrgbench/estimator/split_coriolis_mixing.hpp"

namespace hrgbench::estimator {
namespace {

using Complex = std::complex<double>;
using Q = EngineeringQuantity;
constexpr double kPi = std::numbers::pi;
constexpr double kDegPerRad = 180.0 / kPi;
constexpr std::size_t kCount = kEngineeringQuantityCount;

constexpr std::size_t Index(Q q) { return static_cast<std::size_t>(q); }

// Axes live modulo 90° on the shell: a difference of two of them is folded into (−45°, 45°].
bool IsAxis(std::size_t i) { return i == Index(Q::kDampingAxis) || i == Index(Q::kFrequencyAxis); }
double FoldAxisDifference(double d) {
  d = std::remainder(d, 90.0);
  return d;
}

// Bit i: the quantity depends on parameter i of (δ1..δ6, ξ1..ξ4).
unsigned DependencyBits(Q q) noexcept {
  switch (q) {
    case Q::kResonantFrequency:
      return 0u;
    case Q::kDecayTime:
    case Q::kQualityFactor:
      return 1u << 0;
    case Q::kSlowModeDecayTime:
    case Q::kFastModeDecayTime:
      return (1u << 0) | (1u << 2) | (1u << 3) | (1u << 4) | (1u << 5);
    case Q::kDampingSplit:
    case Q::kDampingAxis:
      return (1u << 2) | (1u << 3);
    case Q::kFrequencySplit:
    case Q::kFrequencyAxis:
      return (1u << 4) | (1u << 5);
    case Q::kAngularGain:
      return 1u << 1;
    case Q::kPickoffGainMismatch:
    case Q::kPickoffPhaseMismatch:
      return (1u << 6) | (1u << 7);
    case Q::kPickoffCrossTalk:
      return 1u << 8;
    case Q::kElectrodeAngle:
      return 1u << 9;
  }
  return 0u;
}

// The significance of a split vector (parameters a, b of the 10) against zero: vᵀ·Σv⁻¹·v, or NaN
// when either was not estimated or Σv is singular.
double SplitChi2(const Eigen::Matrix<double, 10, 1>& p, const std::array<int, 10>& column,
                 const Eigen::MatrixXd& covariance, int a, int b) {
  if (column[a] < 0 || column[b] < 0) return kNaN;
  const Eigen::Index n = covariance.rows();
  if (covariance.cols() != n || column[a] >= n || column[b] >= n) return kNaN;
  Eigen::Matrix2d s;
  s << covariance(column[a], column[a]), covariance(column[a], column[b]),
      covariance(column[b], column[a]), covariance(column[b], column[b]);
  const Eigen::Vector2d v(p[a], p[b]);
  if (!s.allFinite() || !v.allFinite() || s.determinant() <= 0.0) return kNaN;
  return v.dot(s.ldlt().solve(v));
}

std::string Format(double v) {
  if (!std::isfinite(v)) return "—";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

// A value and its std as a metrologist writes them: the std to two significant digits and the
// value to the same decimal place ("999.9993 ± 0.0047"); scientific notation with a common
// exponent when fixed notation would be long ("(4.3 ± 5.4)e-08" is written "4.3e-08 ± 5.4e-08").
// Without a std: six significant digits.
std::pair<std::string, std::string> FormatWithStd(double value, double std) {
  if (!std::isfinite(value)) return {"—", ""};
  if (!(std::isfinite(std) && std > 0.0)) return {Format(value), ""};
  const int std_exponent = static_cast<int>(std::floor(std::log10(std)));
  const int decimals = 1 - std_exponent;  // two significant digits of the std
  const double magnitude = std::max(std::abs(value), std);
  char v[48], s[48];
  if (decimals >= 0 && decimals <= 8 && magnitude < 1e9) {
    std::snprintf(v, sizeof v, "%.*f", decimals, value);
    std::snprintf(s, sizeof s, "%.*f", decimals, std);
  } else {
    const int value_exponent = static_cast<int>(std::floor(std::log10(magnitude)));
    const int digits = std::clamp(value_exponent - std_exponent + 1, 1, 15);
    std::snprintf(v, sizeof v, "%.*e", digits, value);
    std::snprintf(s, sizeof s, "%.1e", std);
  }
  return {v, s};
}

}  // namespace

const EngineeringQuantityInfo& Info(EngineeringQuantity quantity) noexcept {
  return kEngineeringQuantities[Index(quantity)];
}

bool DependsOn(EngineeringQuantity quantity, int index) noexcept {
  return index >= 0 && index < 10 && (DependencyBits(quantity) >> index & 1u) != 0;
}

std::array<double, kEngineeringQuantityCount> EngineeringValues(
    const Delta& model_delta, const Xi& model_xi, const EngineeringModel& model) noexcept {
  std::array<double, kCount> out;
  out.fill(kNaN);
  const double frequency_hz = model.frequency_hz;
  // 1. The pick-off's own ξ: the split's Coriolis mixing needs f0 (without it, ξ as fitted).
  const Xi pickoff_xi = std::isfinite(frequency_hz) && frequency_hz > 0.0
                            ? PickoffXiFromSlowModel(model_xi, model_delta, frequency_hz)
                            : model_xi;
  // 2. The physical pick-off and its frame; the anisotropies in channel 1's electrode frame.
  const PhysicalPickoff pickoff = PhysicalPickoffFromXi(pickoff_xi, model.cross_talk_stage);
  Delta delta =
      DeltaInElectrodeFrame(model_delta, pickoff.frame_angle + model.frame_angle_offset_rad);
  // 3. The decay the frequency drift adds is not damping.
  if (std::isfinite(model.relative_frequency_rate_per_s))
    delta[kDamping] += 0.5 * model.relative_frequency_rate_per_s;

  const ResonatorParameters r = ResonatorFromDelta(delta, frequency_hz);
  out[Index(Q::kResonantFrequency)] = frequency_hz;
  out[Index(Q::kDecayTime)] = r.decay_time_s;
  out[Index(Q::kQualityFactor)] = kPi * frequency_hz * r.decay_time_s;

  // Eigenvalues δ1 ± λ of A(0, δ) on u (model.md's complex form): the modes' decay rates are
  // −δ1 ∓ Re λ, whichever sign the square root takes.
  const Complex c(delta[kDampingAnisotropyCos], delta[kFrequencyAnisotropyCos]);
  const Complex s(delta[kDampingAnisotropySin], delta[kFrequencyAnisotropySin]);
  const double half_rate_split = std::abs(std::sqrt(c * c + s * s).real());
  const double slow_rate = -delta[kDamping] - half_rate_split;
  const double fast_rate = -delta[kDamping] + half_rate_split;
  out[Index(Q::kSlowModeDecayTime)] = slow_rate > 0.0 ? 1.0 / slow_rate : kNaN;
  out[Index(Q::kFastModeDecayTime)] = fast_rate > 0.0 ? 1.0 / fast_rate : kNaN;

  out[Index(Q::kDampingSplit)] = r.damping_anisotropy_per_s;
  out[Index(Q::kDampingAxis)] = 0.5 * r.damping_axis_rad * kDegPerRad;
  out[Index(Q::kFrequencySplit)] = 1e3 * r.frequency_split_hz;
  out[Index(Q::kFrequencyAxis)] = 0.5 * r.frequency_axis_rad * kDegPerRad;
  out[Index(Q::kAngularGain)] = r.angular_gain;

  out[Index(Q::kPickoffGainMismatch)] = 100.0 * (pickoff.pickoff.gain_ratio - 1.0);
  out[Index(Q::kPickoffPhaseMismatch)] = pickoff.pickoff.phase_mismatch_rad * kDegPerRad;
  out[Index(Q::kPickoffCrossTalk)] = 100.0 * pickoff.pickoff.cross_talk;
  out[Index(Q::kElectrodeAngle)] = 0.5 * pickoff.pickoff.electrode_angle_error_rad * kDegPerRad;
  return out;
}

std::array<double, kEngineeringQuantityCount> EngineeringValues(const Delta& delta, const Xi& xi,
                                                                double frequency_hz) noexcept {
  EngineeringModel model;
  model.frequency_hz = frequency_hz;
  return EngineeringValues(delta, xi, model);
}

FrequencyDrift FittedFrequencyDrift(const FitDiagnostics& diagnostics,
                                    double frequency_hz) noexcept {
  FrequencyDrift out;
  if (!(std::isfinite(frequency_hz) && frequency_hz > 0.0)) return out;
  const double omega0 = 2.0 * kPi * frequency_hz;
  double weight = 0.0, sum = 0.0, sum_squares = 0.0;
  for (const RunFitDiagnostics& run : diagnostics.runs) {
    const double rate = run.common_frequency_drift_rad_s2 / omega0;
    if (!std::isfinite(rate) || run.samples == 0) continue;
    const double w = static_cast<double>(run.samples);
    weight += w;
    sum += w * rate;
    sum_squares += rate * rate;
    ++out.runs;
  }
  if (out.runs == 0) return out;
  out.relative_rate_per_s = sum / weight;
  if (out.runs >= 2) {
    // The plain sample std of the runs' rates (not weighted): how far the fit's own weighting
    // could move the mean.
    double mean = 0.0;
    for (const RunFitDiagnostics& run : diagnostics.runs) {
      const double rate = run.common_frequency_drift_rad_s2 / omega0;
      if (std::isfinite(rate) && run.samples > 0) mean += rate;
    }
    mean /= out.runs;
    out.spread_per_s =
        std::sqrt(std::max(0.0, (sum_squares - out.runs * mean * mean) / (out.runs - 1)));
  }
  return out;
}

namespace {

using Values = std::array<double, kCount>;

// Half the difference of two maps' values, axes folded: the sensitivity a budget line needs.
Values HalfDifference(const Values& up, const Values& down) {
  Values out;
  for (std::size_t k = 0; k < kCount; ++k) {
    double d = up[k] - down[k];
    if (IsAxis(k)) d = FoldAxisDifference(d);
    out[k] = 0.5 * d;
  }
  return out;
}

void AddComponent(EngineeringValue* v, std::string source, double u, bool systematic,
                  std::string note) {
  v->budget.push_back({std::move(source), u, systematic, std::move(note)});
}

}  // namespace

EngineeringQuantities ComputeEngineeringQuantities(const EstimateSummary& summary,
                                                   double frequency_hz,
                                                   const EngineeringOptions& options) {
  EngineeringQuantities out;
  out.frequency_hz = frequency_hz;
  out.coverage_factor = options.coverage_factor;
  out.cross_talk_stage = options.cross_talk_stage;

  // The 10 parameters, and where each estimated one sits in the covariance (−1: held).
  Eigen::Matrix<double, 10, 1> p;
  p << summary.delta, summary.xi;
  std::array<int, 10> column;
  column.fill(-1);
  int next = 0;
  for (int i = 0; i < 6; ++i)
    if (summary.delta_estimated[static_cast<std::size_t>(i)]) column[i] = next++;
  for (int i = 0; i < 4; ++i)
    if (summary.xi_estimated[static_cast<std::size_t>(i)]) column[6 + i] = next++;
  const bool has_covariance = summary.covariance.rows() == next &&
                              summary.covariance.cols() == next && summary.covariance.allFinite();

  const FrequencyDrift drift = FittedFrequencyDrift(summary.diagnostics, frequency_hz);
  EngineeringModel model;
  model.frequency_hz = frequency_hz;
  model.cross_talk_stage = options.cross_talk_stage;
  model.relative_frequency_rate_per_s =
      std::isfinite(drift.relative_rate_per_s) ? drift.relative_rate_per_s : 0.0;
  out.relative_frequency_rate_per_s = drift.relative_rate_per_s;

  const auto values_at = [&](const Eigen::Matrix<double, 10, 1>& q, const EngineeringModel& m) {
    return EngineeringValues(q.head<6>(), q.tail<4>(), m);
  };
  const Values value = values_at(p, model);
  {
    const Xi pickoff_xi = std::isfinite(frequency_hz) && frequency_hz > 0.0
                              ? PickoffXiFromSlowModel(summary.xi, summary.delta, frequency_hz)
                              : summary.xi;
    out.pickoff_frame_angle_rad =
        PhysicalPickoffFromXi(pickoff_xi, options.cross_talk_stage).frame_angle;
  }

  // Delta method: J·Σ·Jᵀ with J by central differences along each estimated parameter.
  Values variance;
  variance.fill(has_covariance ? 0.0 : kNaN);
  if (has_covariance && next > 0) {
    Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(kCount, next);
    for (int i = 0; i < 10; ++i) {
      if (column[i] < 0) continue;
      const double step = 1e-3 * std::sqrt(summary.covariance(column[i], column[i]));
      if (!(step > 0.0)) continue;
      Eigen::Matrix<double, 10, 1> plus = p, minus = p;
      plus[i] += step;
      minus[i] -= step;
      const Values half = HalfDifference(values_at(plus, model), values_at(minus, model));
      for (std::size_t k = 0; k < kCount; ++k)
        jacobian(static_cast<Eigen::Index>(k), column[i]) = half[k] / step;
    }
    const Eigen::MatrixXd propagated = jacobian * summary.covariance * jacobian.transpose();
    for (std::size_t k = 0; k < kCount; ++k)
      variance[k] = propagated(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k));
  }

  // The systematic components: each a map with one input moved, against the nominal one.
  // The cross-talk's stage: from the middle, the farther of the two ends is the half-width; a
  // stage the station declared has none.
  const bool stage_declared = options.cross_talk_stage != CrossTalkStage::kMidway;
  Values stage_half_width;
  stage_half_width.fill(0.0);
  if (!stage_declared) {
    for (const CrossTalkStage end : {CrossTalkStage::kBeforeGain, CrossTalkStage::kAfterGain}) {
      EngineeringModel at_end = model;
      at_end.cross_talk_stage = end;
      const Values half = HalfDifference(values_at(p, at_end), value);
      for (std::size_t k = 0; k < kCount; ++k)
        stage_half_width[k] = std::max(stage_half_width[k], 2.0 * std::abs(half[k]));
    }
  }
  // Half the change of every value when one input of the map moves down and up by one step
  // (`move(model, ±1)` moves it): the sensitivity each of the budget lines below is sized by.
  const auto swing = [&](const auto& move) {
    EngineeringModel up = model, down = model;
    move(up, 1.0);
    move(down, -1.0);
    return HalfDifference(values_at(p, up), values_at(p, down));
  };
  const double bound = options.unmodelled_coupling_bound_rad;
  Values coupling_u;
  coupling_u.fill(0.0);
  if (bound > 0.0) {
    for (const std::complex<double> direction :
         {std::complex<double>(1.0, 0.0), std::complex<double>(0.0, 1.0)}) {
      const Values half = swing([&](EngineeringModel& m, double sign) {
        m.frame_angle_offset_rad = sign * bound * direction;
      });
      for (std::size_t k = 0; k < kCount; ++k) coupling_u[k] += half[k] * half[k] / 3.0;
    }
    for (double& u : coupling_u) u = std::sqrt(u);
  }
  Values drift_u;
  drift_u.fill(kNaN);
  if (std::isfinite(drift.spread_per_s)) {
    drift_u = swing([&](EngineeringModel& m, double sign) {
      m.relative_frequency_rate_per_s += sign * drift.spread_per_s;
    });
    for (double& u : drift_u) u = std::abs(u);
  }
  Values f0_u;
  f0_u.fill(kNaN);
  if (std::isfinite(options.frequency_std_hz) && std::isfinite(frequency_hz)) {
    f0_u = swing([&](EngineeringModel& m, double sign) {
      m.frequency_hz += sign * options.frequency_std_hz;
    });
    for (double& u : f0_u) u = std::abs(u);
  }
  // Ω taken as exact for some runs: what a 1e-6 rad/s error of one run's Ω would move each
  // quantity by (the largest over those runs; the fit's linearised sensitivity).
  Values omega_shift;
  omega_shift.fill(0.0);
  int omega_worst_run = 0;
  for (const OmegaSensitivity& run : summary.omega_sensitivity) {
    Eigen::Matrix<double, 10, 1> moved = p;
    for (int i = 0; i < 6; ++i)
      if (std::isfinite(run.delta[i])) moved[i] += run.delta[i];
    for (int i = 0; i < 4; ++i)
      if (std::isfinite(run.xi[i])) moved[6 + i] += run.xi[i];
    const Values half = HalfDifference(values_at(moved, model), value);
    for (std::size_t k = 0; k < kCount; ++k) {
      if (2.0 * std::abs(half[k]) > omega_shift[k]) {
        omega_shift[k] = 2.0 * std::abs(half[k]);
        if (k == Index(Q::kAngularGain)) omega_worst_run = run.run_id;
      }
    }
  }
  // Which inputs each quantity's map actually reads (the rest cannot move it).
  const auto uses_pickoff_frame = [](Q q) {
    return q != Q::kResonantFrequency && q != Q::kDecayTime && q != Q::kQualityFactor &&
           q != Q::kAngularGain;
  };
  const auto uses_drift = [](Q q) {
    return q == Q::kDecayTime || q == Q::kQualityFactor || q == Q::kSlowModeDecayTime ||
           q == Q::kFastModeDecayTime;
  };

  const std::string fit_note =
      "covariance " + summary.diagnostics.covariance_kind + ", noise shape " +
      summary.diagnostics.noise_shape +
      (summary.diagnostics.omega_nuisance
           ? "; the recorded Ω uncertainty is inside it (a prior of the fit)"
           : "; Ω taken as exact (no Ω uncertainty recorded): its error is not in it");
  const bool usable = summary.IsUsable();
  for (std::size_t k = 0; k < kCount; ++k) {
    const Q q = static_cast<Q>(k);
    EngineeringValue& v = out.values[k];
    v.value = value[k];
    v.determined = usable && std::isfinite(v.value);
    if (!usable) v.note = "the estimate is not usable";
    for (int dependency = 0; dependency < 10; ++dependency) {
      if (DependsOn(q, dependency) && column[dependency] < 0) {
        v.determined = false;
        v.note = dependency < 6 ? std::string(kDeltaNames[static_cast<std::size_t>(dependency)]) +
                                      " was held, not estimated"
                                : std::string(kXiNames[static_cast<std::size_t>(dependency - 6)]) +
                                      " was held, not estimated";
        break;
      }
    }
    if (usable && !std::isfinite(v.value) && v.note.empty()) {
      v.note = q == Q::kQualityFactor || q == Q::kResonantFrequency
                   ? "the resonant frequency is unknown"
                   : "not finite (a mode that does not decay?)";
    }
    if (q == Q::kResonantFrequency) {
      // Reported by the electronics, not estimated.
      if (std::isfinite(options.frequency_std_hz)) {
        v.std = options.frequency_std_hz;
        AddComponent(&v, "f0 as reported", v.std, true, options.frequency_std_source);
      } else {
        AddComponent(&v, "f0 as reported", kNaN, true,
                     "not stated by the electronics: f0 taken as exact");
      }
      continue;
    }
    if (!v.determined || !(variance[k] >= 0.0)) continue;

    v.statistical_std = std::sqrt(variance[k]);
    AddComponent(&v, "fit (statistical)", v.statistical_std, false, fit_note);
    if (!summary.omega_sensitivity.empty()) {
      AddComponent(&v, "Ω metrology", kNaN, true,
                   "Ω taken as exact for " + std::to_string(summary.omega_sensitivity.size()) +
                       " run(s) (no uncertainty recorded): not evaluated; a 1e-6 rad/s error of "
                       "one run's Ω moves it by up to " +
                       Format(omega_shift[k]) +
                       (q == Q::kAngularGain && omega_worst_run != 0
                            ? " (run " + std::to_string(omega_worst_run) + ")"
                            : std::string()));
    }
    if (uses_pickoff_frame(q)) {
      AddComponent(
          &v, "pick-off model: cross-talk stage", stage_half_width[k] / std::sqrt(3.0), true,
          stage_declared ? std::string("declared ") + ToString(options.cross_talk_stage)
                         : "midway between the electrode lines and the amplified channels; either "
                           "end moves it by up to " +
                               Format(stage_half_width[k]) +
                               " (rectangular half-width); free runs cannot tell them apart");
      if (bound > 0.0) {
        AddComponent(&v, "pick-off model: unmodelled antisymmetric coupling", coupling_u[k], true,
                     "declared bound ±" + Format(bound) +
                         " rad on both parts of the frame angle (rectangular)");
      } else {
        AddComponent(&v, "pick-off model: unmodelled antisymmetric coupling", kNaN, true,
                     "no bound declared: only the nominal pick-off model's couplings are "
                     "corrected");
      }
      if (!(std::isfinite(frequency_hz) && frequency_hz > 0.0) &&
          (q == Q::kPickoffGainMismatch || q == Q::kElectrodeAngle)) {
        AddComponent(&v, "split's Coriolis mixing", kNaN, true,
                     "f0 unknown: the mixing −(δ5, δ6)/(2ω0) stays in the value");
      }
    }
    if (uses_drift(q)) {
      if (!std::isfinite(drift.relative_rate_per_s)) {
        AddComponent(&v, "frequency drift correction", kNaN, true,
                     std::isfinite(frequency_hz)
                         ? "not corrected: the fit's common phase has no drift term"
                         : "not corrected: f0 unknown");
      } else if (std::isfinite(drift_u[k])) {
        AddComponent(&v, "frequency drift correction", drift_u[k], true,
                     "½·ω̇/ω0 = " + Format(0.5 * drift.relative_rate_per_s) +
                         " 1/s added to δ1; spread of the " + std::to_string(drift.runs) +
                         " runs' drifts");
      } else {
        AddComponent(&v, "frequency drift correction", kNaN, true,
                     "½·ω̇/ω0 = " + Format(0.5 * drift.relative_rate_per_s) +
                         " 1/s added to δ1; one run: its spread cannot be judged");
      }
    }
    if (q == Q::kFrequencySplit && std::isfinite(drift.relative_rate_per_s)) {
      // The split scales with f (a temperature moves both modes alike): over a run of T it sweeps
      // Δf·|ω̇/ω0|·T around the fit's one δ5, δ6, the runs' mean (rectangular, half of it).
      const double sweep = v.value * std::abs(drift.relative_rate_per_s) * options.longest_run_s;
      if (std::isfinite(sweep)) {
        AddComponent(&v, "frequency drift: the split follows f", 0.5 * sweep / std::sqrt(3.0), true,
                     "the split sweeps " + Format(sweep) + " mHz over the longest run (" +
                         Format(options.longest_run_s) +
                         " s) at the fitted drift: the value is the runs' mean, at their mean "
                         "temperature");
      } else {
        AddComponent(&v, "frequency drift: the split follows f", kNaN, true,
                     "the runs' length is unknown: the split's sweep over a run is not evaluated");
      }
    }
    if (q == Q::kQualityFactor) {
      AddComponent(&v, "f0 as reported", f0_u[k], true,
                   std::isfinite(f0_u[k]) ? "u(f0) = " + Format(options.frequency_std_hz) +
                                                " Hz: " + options.frequency_std_source
                                          : "not stated by the electronics: f0 taken as exact");
    }
    double combined = 0.0;
    for (const UncertaintyComponent& c : v.budget)
      if (std::isfinite(c.standard_uncertainty))
        combined += c.standard_uncertainty * c.standard_uncertainty;
    v.std = std::sqrt(combined);
    std::stable_sort(v.budget.begin(), v.budget.end(),
                     [](const UncertaintyComponent& a, const UncertaintyComponent& b) {
                       const bool fa = std::isfinite(a.standard_uncertainty);
                       const bool fb = std::isfinite(b.standard_uncertainty);
                       if (fa != fb) return fa;
                       return fa && a.standard_uncertainty > b.standard_uncertainty;
                     });
  }

  // Axes of splits that are not significantly different from zero are undetermined.
  const struct {
    Q split, axis;
    int a, b;
  } splits[] = {{Q::kDampingSplit, Q::kDampingAxis, 2, 3},
                {Q::kFrequencySplit, Q::kFrequencyAxis, 4, 5}};
  for (const auto& s : splits) {
    EngineeringValue& axis = out[s.axis];
    if (!axis.determined) continue;
    const double chi2 = SplitChi2(p, column, summary.covariance, s.a, s.b);
    if (!(chi2 >= options.axis_significance_chi2)) {
      const std::string why =
          std::isfinite(chi2)
              ? "the split is not significantly different from zero (chi2 = " + Format(chi2) +
                    " below " + Format(options.axis_significance_chi2) + ")"
              : "the split's significance cannot be judged (no covariance)";
      axis.value = kNaN;
      axis.std = kNaN;
      axis.statistical_std = kNaN;
      axis.budget.clear();
      axis.determined = false;
      axis.note = "undetermined: " + why;
      out[s.split].note = "not significantly different from zero";
    }
  }

  out.limitations = {
      "Free runs cannot tell the pick-off's antisymmetric coupling (a complex frame angle) from "
      "the anisotropies' own angles: the axes and the damping split are corrected with the "
      "nominal pick-off model's coupling (a = " +
          Format(out.pickoff_frame_angle_rad.real()) +
          (out.pickoff_frame_angle_rad.imag() < 0 ? " − " : " + ") +
          Format(std::abs(out.pickoff_frame_angle_rad.imag())) +
          "i rad), and what that model does not fix is a systematic component.",
      "The fit's δ1 includes the decay a frequency drift adds (½·ω̇/ω): τ, τ1, τ2 and Q are "
      "corrected with the runs' fitted drifts.",
  };
  return out;
}

std::string EngineeringQuantities::Report() const {
  // Characters, not bytes: labels carry τ, Δ, θ, ω and a missing value is "—".
  const auto width = [](std::string_view text) {
    std::size_t n = 0;
    for (char c : text) n += (static_cast<unsigned char>(c) & 0xC0) != 0x80 ? 1 : 0;
    return n;
  };
  const auto pad_to = [&](std::string text, std::size_t column, bool left) {
    const std::size_t w = width(text);
    const std::string fill(w < column ? column - w : 1, ' ');
    return left ? text + fill : fill + text;
  };
  std::string text;
  for (std::size_t k = 0; k < kCount; ++k) {
    const EngineeringQuantityInfo& info = kEngineeringQuantities[k];
    const EngineeringValue& v = values[k];
    const auto [value, std] = FormatWithStd(v.value, v.std);
    text += "  " + pad_to(std::string(info.label), 52, true) + pad_to(value, 14, false);
    if (!std.empty()) text += " ± " + std;
    if (!info.unit.empty()) text += " " + std::string(info.unit);
    // The statistical part alone, when the rest of the budget is more than a tenth of it.
    if (std::isfinite(v.statistical_std) && std::isfinite(v.std) &&
        v.std > 1.1 * v.statistical_std && !v.budget.empty()) {
      text += "  [fit " + FormatWithStd(v.value, v.statistical_std).second +
              "; largest: " + v.budget.front().source + "]";
    }
    if (!v.note.empty()) text += "  (" + v.note + ")";
    text += "\n";
  }
  text += "  (± is the combined standard uncertainty u_c; expanded U = " + Format(coverage_factor) +
          "·u_c)\n";
  return text;
}

std::string EngineeringQuantities::BudgetReport() const {
  std::string text;
  for (std::size_t k = 0; k < kCount; ++k) {
    const EngineeringQuantityInfo& info = kEngineeringQuantities[k];
    const EngineeringValue& v = values[k];
    if (v.budget.empty()) continue;
    const std::string unit = info.unit.empty() ? "" : " " + std::string(info.unit);
    text += std::string(info.name) + ": u_c = " + Format(v.std) + unit +
            ", U (k = " + Format(coverage_factor) + ") = " + Format(coverage_factor * v.std) +
            unit + "\n";
    for (const UncertaintyComponent& c : v.budget) {
      text += "    " + c.source + (c.systematic ? " (B)" : " (A)") + ": " +
              (std::isfinite(c.standard_uncertainty) ? Format(c.standard_uncertainty) + unit
                                                     : std::string("not evaluated")) +
              " — " + c.note + "\n";
    }
  }
  for (const std::string& l : limitations) text += "note: " + l + "\n";
  return text;
}

}  // namespace hrgbench::estimator
