#include "hrgbench/estimator/engineering_quantities.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <utility>

#include <Eigen/Dense>

#include "hrgbench/estimator/physical_parameters.hpp"

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

std::array<double, kEngineeringQuantityCount> EngineeringValues(const Delta& delta, const Xi& xi,
                                                                double frequency_hz) noexcept {
  std::array<double, kCount> out;
  out.fill(kNaN);
  const ResonatorParameters r = ResonatorFromDelta(delta, frequency_hz);
  out[Index(Q::kResonantFrequency)] = frequency_hz;
  out[Index(Q::kDecayTime)] = r.decay_time_s;
  out[Index(Q::kQualityFactor)] = kPi * frequency_hz * r.decay_time_s;

  // Eigenvalues δ1 ± λ of A(0, δ) on u (MODEL.md's complex form): the modes' decay rates are
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

  const PickoffParameters pickoff = PickoffFromXi(xi);
  out[Index(Q::kPickoffGainMismatch)] = 100.0 * (pickoff.gain_ratio - 1.0);
  out[Index(Q::kPickoffPhaseMismatch)] = pickoff.phase_mismatch_rad * kDegPerRad;
  out[Index(Q::kPickoffCrossTalk)] = 100.0 * pickoff.cross_talk;
  out[Index(Q::kElectrodeAngle)] = 0.5 * pickoff.electrode_angle_error_rad * kDegPerRad;
  return out;
}

EngineeringQuantities ComputeEngineeringQuantities(const EstimateSummary& summary,
                                                   double frequency_hz,
                                                   const EngineeringOptions& options) {
  EngineeringQuantities out;
  out.frequency_hz = frequency_hz;

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

  const auto values_at = [&](const Eigen::Matrix<double, 10, 1>& q) {
    return EngineeringValues(q.head<6>(), q.tail<4>(), frequency_hz);
  };
  const std::array<double, kCount> value = values_at(p);

  // Delta method: J·Σ·Jᵀ with J by central differences along each estimated parameter.
  std::array<double, kCount> variance;
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
      const std::array<double, kCount> up = values_at(plus), down = values_at(minus);
      for (std::size_t k = 0; k < kCount; ++k) {
        double d = up[k] - down[k];
        if (IsAxis(k)) d = FoldAxisDifference(d);
        jacobian(static_cast<Eigen::Index>(k), column[i]) = d / (2.0 * step);
      }
    }
    const Eigen::MatrixXd propagated = jacobian * summary.covariance * jacobian.transpose();
    for (std::size_t k = 0; k < kCount; ++k)
      variance[k] = propagated(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k));
  }

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
      v.std = kNaN;  // reported by the electronics, not estimated
    } else if (v.determined && variance[k] >= 0.0) {
      v.std = std::sqrt(variance[k]);
    }
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
      axis.determined = false;
      axis.note = "undetermined: " + why;
      out[s.split].note = "not significantly different from zero";
    }
  }
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
    if (!v.note.empty()) text += "  (" + v.note + ")";
    text += "\n";
  }
  return text;
}

}  // namespace hrgbench::estimator
