#pragma once
// LimitsConfig: the product's acceptance limits (bench_configs/limits-*.toml): an allowed range
// [min, max] for any of the estimated parameters δ1…δ6, ξ1…ξ4, for the fit's residual RMS and
// noise σ̂, and for the engineering quantities in the field's units (tau_s, q_factor,
// frequency_split_mhz, ..., estimator/engineering_quantities.hpp). A quantity without a limit is
// not judged. The verdict (verdict.hpp) applies them to an estimate: outside its range is a FAIL of
// the unit (STYLE rule 9).
//
// The fit itself is always judged: [fit] (optional) sets how far outside the model a fit may be
// before no limit is trusted (estimator::FitQualityLimits; its defaults when the table is absent).
//
// [decision] (optional) declares the decision rule and its coverage factor (decision_rule.hpp).
//
// [tune] (optional) limits the tuned gyro's rate error on the table (TuneLimits).
//
// Loading is strict (STYLE rule 10); errors name file, line, key and value. Not thread-safe; not
// for real-time use. Loaders return std::expected, never throw (except std::bad_alloc).

#include <array>
#include <cstddef>
#include <expected>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hrgbench/config/config_error.hpp"
#include "hrgbench/config/decision_rule.hpp"
#include "hrgbench/estimator/engineering_quantities.hpp"
#include "hrgbench/estimator/fit_diagnostics.hpp"

namespace hrgbench::bench {

// What a limit can be put on; the names are the keys in the file and in the verdict. The
// engineering quantities (estimator/engineering_quantities.hpp: τ, Q, splits and axes on the shell,
// k, the pick-off errors in % and degrees) follow in the estimator's order and under its names.
enum class LimitedQuantity {
  kDelta1,
  kDelta2,
  kDelta3,
  kDelta4,
  kDelta5,
  kDelta6,
  kXi1,
  kXi2,
  kXi3,
  kXi4,
  kResidualRms,
  kNoiseSigma,
  kFirstEngineering,  // = estimator::EngineeringQuantity::kResonantFrequency, then the others
};
inline constexpr std::size_t kFirstEngineeringLimit =
    static_cast<std::size_t>(LimitedQuantity::kFirstEngineering);
inline constexpr std::size_t kLimitedQuantityCount =
    kFirstEngineeringLimit + estimator::kEngineeringQuantityCount;
inline constexpr std::array<std::string_view, kLimitedQuantityCount> kLimitedQuantityNames = {
    "delta1", "delta2", "delta3", "delta4", "delta5", "delta6", "xi1", "xi2", "xi3", "xi4",
    "residual_rms", "noise_sigma",
    // estimator::kEngineeringQuantities' names (a static_assert in the loader keeps them equal)
    "resonant_frequency_hz", "tau_s", "q_factor", "tau1_s", "tau2_s", "damping_split_per_s",
    "damping_axis_deg", "frequency_split_mhz", "frequency_axis_deg", "angular_gain",
    "gain_mismatch_percent", "phase_mismatch_deg", "cross_talk_percent", "electrode_angle_deg"};

// The engineering quantity a limit is on (nullopt for δ, ξ and the fit's numbers).
std::optional<estimator::EngineeringQuantity> EngineeringOf(LimitedQuantity quantity) noexcept;
// The limit on an engineering quantity.
LimitedQuantity LimitOf(estimator::EngineeringQuantity quantity) noexcept;

std::string_view ToString(LimitedQuantity quantity) noexcept;

// The smallest value the quantity can physically take (a magnitude, a decay time, an RMS: 0), or
// −∞ for a signed one. A limit's min at or below it is the physics' bound, not a tolerance, so
// the decision rule does not guard it (decision_rule.hpp).
double PhysicalMinimum(LimitedQuantity quantity) noexcept;

struct ParameterLimit {
  LimitedQuantity quantity = LimitedQuantity::kDelta1;
  double min = 0.0;      // inclusive; same unit as the parameter (bench_configs/README.md)
  double max = 0.0;      // inclusive; min <= max
  std::size_t line = 0;  // where the limit was written
};

// [tune] (optional): the limits `hrg-bench tune` judges its verification against
// (bench/tuning/tune_verdict.hpp), in the field's units, each a maximum; an absent key is not
// judged. The rate error and the stability figures are magnitudes (their low side is the physical
// bound, not guarded); the bias and the scale-factor error are signed and judged in [−max, max].
struct TuneLimits {
  std::optional<double> rate_error_deg_h;  // the angle-dependent rate error after, at every rate
  std::optional<double> bias_deg_h;        // the rate output's bias over the verification's rates
  std::optional<double> scale_factor_ppm;  // its scale-factor error
  // Its asymmetry, ε+ − ε− (analysis/scale_factor.hpp): needs rates of both signs and two
  // magnitudes (hrg-bench tune --rates 0.3 -0.3 1 -1), else not judgeable (ERROR).
  std::optional<double> scale_factor_asymmetry_ppm;
  std::optional<double> arw_deg_per_sqrt_h;      // angle random walk (the zero-rate hold's)
  std::optional<double> bias_instability_deg_h;  // bias instability (the zero-rate hold's)
  // At every rate the angle-dependent rate error falls by this factor, or to within what the
  // estimate's uncertainty predicts, whichever is larger (issue 28's bound; always judged).
  double min_improvement = 100.0;
  std::size_t line = 0;  // where [tune] was written; 0 = not in the file
};

struct LimitsConfig {
  std::filesystem::path file;  // where it was loaded from; empty: no limits file
  std::string sha256_hex;      // SHA-256 of the file's bytes; empty: no limits file

  std::string name;  // [limits] name (required in a file)
  std::string description;
  // [limits] product: the product these limits specify ("HRG-30 grade A"); "" when not said. The
  // limits file is the product's specification, so it names the product (the results store's
  // session.product, hrg-results stats --by product).
  std::string product;
  std::vector<ParameterLimit>
      limits;  // in the order of LimitedQuantity; each quantity at most once
  // How far outside its model a fit may be ([fit]; the defaults when absent).
  estimator::FitQualityLimits fit;
  std::size_t fit_line = 0;  // where [fit] was written; 0 = not in the file (defaults)
  // How a value with its uncertainty is accepted or rejected ([decision]; the defaults when
  // absent: guarded acceptance with retest, k = 2).
  DecisionRule decision;
  TuneLimits tune;  // [tune]; the defaults when absent
};

std::expected<LimitsConfig, config_file::ConfigError> LoadLimitsConfig(
    const std::filesystem::path& file);
std::expected<LimitsConfig, config_file::ConfigError> ParseLimitsConfig(
    std::string_view toml_text, const std::filesystem::path& file);

}  // namespace hrgbench::bench
