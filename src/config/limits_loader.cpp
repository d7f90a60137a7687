// Loader of limits files.

#include <limits>
#include <optional>
#include <string>
#include <utility>

#include "hrgbench/config/limits_config.hpp"
#include "hrgbench/config/toml_reader.hpp"

namespace hrgbench::bench {
namespace {

constexpr bool EngineeringNamesAgree() {
  for (std::size_t i = 0; i < estimator::kEngineeringQuantityCount; ++i)
    if (kLimitedQuantityNames[kFirstEngineeringLimit + i] !=
        estimator::kEngineeringQuantities[i].name)
      return false;
  return true;
}
static_assert(EngineeringNamesAgree(), "limit names must be the estimator's engineering names");

using namespace config_file;  // NOLINT(google-build-using-namespace): the loader's vocabulary

std::expected<ParameterLimit, ConfigError> ReadLimit(const TableReader& reader,
                                                     const toml::node& node,
                                                     LimitedQuantity quantity) {
  const std::string_view key = ToString(quantity);
  HRG_TRY(range, VectorFrom<2>(reader, node, key, kAnyFinite));
  ParameterLimit limit;
  limit.quantity = quantity;
  limit.min = (*range)(0);
  limit.max = (*range)(1);
  limit.line = LineOf(node);
  if (limit.min > limit.max) {
    return std::unexpected(
        reader.Error(node, key, "out of range: must be [min, max] with min <= max"));
  }
  if ((quantity == LimitedQuantity::kResidualRms || quantity == LimitedQuantity::kNoiseSigma) &&
      limit.min < 0.0) {
    return std::unexpected(
        reader.Error(node, key, "out of range: an RMS or a sigma is >= 0, so min must be >= 0"));
  }
  return limit;
}

std::expected<LimitsConfig, ConfigError> ReadLimits(const TomlDocument& document,
                                                    const std::filesystem::path& file) {
  const Source source(file, document.text);
  LimitsConfig limits;
  limits.file = file;
  limits.sha256_hex = document.sha256_hex;
  TableReader root(document.root, "", source);

  HRG_TRY(header, SubTable(root, "limits", true));
  TableReader reader(**header, "limits", source);
  HRG_TRY(name, RequiredString(reader, "name"));
  limits.name = *name;
  HRG_TRY(description, OptionalString(reader, "description", "", false, StringKind::kDescription));
  limits.description = *description;
  HRG_TRY(product, OptionalString(reader, "product", "", false));
  limits.product = *product;
  for (std::size_t q = 0; q < kLimitedQuantityCount; ++q) {
    const auto quantity = static_cast<LimitedQuantity>(q);
    const toml::node* node = reader.Find(ToString(quantity));
    if (node == nullptr) continue;
    HRG_TRY(limit, ReadLimit(reader, *node, quantity));
    limits.limits.push_back(*limit);
  }
  HRG_CHECK(reader.Unknown(
      "name, description, product, delta1 … delta6, xi1 … xi4, residual_rms, noise_sigma, "
      "resonant_frequency_hz, tau_s, q_factor, tau1_s, tau2_s, damping_split_per_s, "
      "damping_axis_deg, frequency_split_mhz, frequency_axis_deg, angular_gain, "
      "gain_mismatch_percent, phase_mismatch_deg, cross_talk_percent, electrode_angle_deg (each "
      "[min, max])"));

  HRG_TRY(fit_table, SubTable(root, "fit", false));
  if (*fit_table != nullptr) {
    TableReader fit(**fit_table, "fit", source);
    limits.fit_line = LineOf(**fit_table);
    // Bounds: a ratio of 1 is a perfect fit and 100 is no check at all; a normal score beyond
    // 1e6 or a rate offset beyond 1e6 of its std would never be reached either.
    static constexpr Range kRatio{1.0, 100.0, true, "in [1, 100]"};
    static constexpr Range kScore{0.0, 1e6, false, "in (0, 1e6]"};
    HRG_TRY(ratio,
            OptionalNumber(fit, "residual_ratio_max", kRatio, limits.fit.residual_ratio_max));
    HRG_TRY(white, OptionalNumber(fit, "whiteness_z_max", kScore, limits.fit.whiteness_z_max));
    HRG_TRY(omega, OptionalNumber(fit, "omega_offset_max_in_std", kScore,
                                  limits.fit.omega_offset_max_in_std));
    limits.fit.residual_ratio_max = *ratio;
    limits.fit.whiteness_z_max = *white;
    limits.fit.omega_offset_max_in_std = *omega;
    HRG_CHECK(fit.Unknown("residual_ratio_max, whiteness_z_max, omega_offset_max_in_std"));
  }
  HRG_TRY(decision_table, SubTable(root, "decision", false));
  if (*decision_table != nullptr) {
    TableReader decision(**decision_table, "decision", source);
    limits.decision.line = LineOf(**decision_table);
    HRG_TRY(rule, Choice(decision, "rule",
                         {kDecisionRuleNames[0], kDecisionRuleNames[1], kDecisionRuleNames[2]}, 0));
    limits.decision.kind = static_cast<DecisionRuleKind>(*rule);
    static constexpr Range kCoverage{kMinCoverageFactor, kMaxCoverageFactor, true, "in [1, 6]"};
    HRG_TRY(
        k, OptionalNumber(decision, "coverage_factor", kCoverage, limits.decision.coverage_factor));
    limits.decision.coverage_factor = *k;
    // The ratio belongs to simple acceptance alone: under a guarded rule it would be a number the
    // verdict silently ignores.
    if (const toml::node* ratio_node = decision.Find("max_uncertainty_ratio")) {
      if (limits.decision.kind != DecisionRuleKind::kSimpleAcceptance) {
        return std::unexpected(decision.Error(
            *ratio_node, "max_uncertainty_ratio",
            "only with rule = \"simple_acceptance\" (a guarded rule's guard is k·u itself)"));
      }
      static constexpr Range kRatio{0.0, 1.0, false, "in (0, 1]"};
      HRG_TRY(ratio, NumberFrom(decision, *ratio_node, "max_uncertainty_ratio", kRatio));
      limits.decision.max_uncertainty_ratio = *ratio;
    }
    HRG_CHECK(decision.Unknown("rule, coverage_factor, max_uncertainty_ratio"));
  }
  HRG_TRY(tune_table, SubTable(root, "tune", false));
  if (*tune_table != nullptr) {
    TableReader tune(**tune_table, "tune", source);
    limits.tune.line = LineOf(**tune_table);
    // Bounds: 1e6 °/h is 280 °/s, 1e6 ppm a scale factor of 2: no gyro's limit is beyond either.
    static constexpr Range kRate{0.0, 1e6, false, "in (0, 1e6]"};
    const auto optional = [&tune](std::string_view key,
                                  std::optional<double>& into) -> std::optional<ConfigError> {
      const toml::node* node = tune.Find(key);
      if (node == nullptr) return std::nullopt;
      auto value = NumberFrom(tune, *node, key, kRate);
      if (!value) return std::move(value).error();
      into = *value;
      return std::nullopt;
    };
    HRG_CHECK(optional("rate_error_deg_h", limits.tune.rate_error_deg_h));
    HRG_CHECK(optional("bias_deg_h", limits.tune.bias_deg_h));
    HRG_CHECK(optional("scale_factor_ppm", limits.tune.scale_factor_ppm));
    HRG_CHECK(optional("scale_factor_asymmetry_ppm", limits.tune.scale_factor_asymmetry_ppm));
    HRG_CHECK(optional("arw_deg_per_sqrt_h", limits.tune.arw_deg_per_sqrt_h));
    HRG_CHECK(optional("bias_instability_deg_h", limits.tune.bias_instability_deg_h));
    static constexpr Range kImprovement{1.0, 1e9, true, "in [1, 1e9]"};
    HRG_TRY(improvement,
            OptionalNumber(tune, "min_improvement", kImprovement, limits.tune.min_improvement));
    limits.tune.min_improvement = *improvement;
    HRG_CHECK(
        tune.Unknown("rate_error_deg_h, bias_deg_h, scale_factor_ppm, "
                     "scale_factor_asymmetry_ppm, arw_deg_per_sqrt_h, bias_instability_deg_h, "
                     "min_improvement"));
  }
  HRG_CHECK(root.Unknown("[limits], [fit], [decision], [tune]"));
  return limits;
}

}  // namespace

std::string_view ToString(LimitedQuantity quantity) noexcept {
  const auto index = static_cast<std::size_t>(quantity);
  return index < kLimitedQuantityCount ? kLimitedQuantityNames[index] : "?";
}

double PhysicalMinimum(LimitedQuantity quantity) noexcept {
  switch (quantity) {
    case LimitedQuantity::kResidualRms:
    case LimitedQuantity::kNoiseSigma:
      return 0.0;
    default:
      break;
  }
  const std::optional<estimator::EngineeringQuantity> e = EngineeringOf(quantity);
  if (!e) return -std::numeric_limits<double>::infinity();
  switch (*e) {
    // Magnitudes and the decay times of a damped resonator (engineering_quantities.hpp): none
    // is below 0, whatever the estimate's noise says.
    case estimator::EngineeringQuantity::kResonantFrequency:
    case estimator::EngineeringQuantity::kDecayTime:
    case estimator::EngineeringQuantity::kQualityFactor:
    case estimator::EngineeringQuantity::kSlowModeDecayTime:
    case estimator::EngineeringQuantity::kFastModeDecayTime:
    case estimator::EngineeringQuantity::kDampingSplit:
    case estimator::EngineeringQuantity::kFrequencySplit:
      return 0.0;
    default:
      return -std::numeric_limits<double>::infinity();
  }
}

std::optional<estimator::EngineeringQuantity> EngineeringOf(LimitedQuantity quantity) noexcept {
  const auto index = static_cast<std::size_t>(quantity);
  if (index < kFirstEngineeringLimit || index >= kLimitedQuantityCount) return std::nullopt;
  return static_cast<estimator::EngineeringQuantity>(index - kFirstEngineeringLimit);
}

LimitedQuantity LimitOf(estimator::EngineeringQuantity quantity) noexcept {
  return static_cast<LimitedQuantity>(kFirstEngineeringLimit + static_cast<std::size_t>(quantity));
}

std::expected<LimitsConfig, ConfigError> ParseLimitsConfig(std::string_view toml_text,
                                                           const std::filesystem::path& file) {
  HRG_TRY(document, ParseTomlText(toml_text, file));
  return ReadLimits(*document, file);
}

std::expected<LimitsConfig, ConfigError> LoadLimitsConfig(const std::filesystem::path& file) {
  HRG_TRY(document, LoadTomlFile(file));
  return ReadLimits(*document, file);
}

}  // namespace hrgbench::bench
