#include <toml++/toml.h>

#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "count_text.hpp"
#include "hrgbench/config/config_bounds.hpp"
#include "hrgbench/config/sim_spec.hpp"
#include "hrgbench/config/toml_reader.hpp"

namespace hrgbench::app {
namespace {

using estimator::RunPlan;

using config_file::kAnyFinite;
using config_file::kMaxRuns;
using config_file::kMaxTotalFreeRunS;
using config_file::kMaxTotalSamples;
using config_file::kNonNegative;
using config_file::kPositive;
using config_file::NumberFrom;
using config_file::OptionalNumber;
using config_file::OptionalString;
using config_file::Range;
using config_file::RequiredVector;
using config_file::Source;
using config_file::SubTable;
using config_file::TableReader;

// The run keys, with the range each must satisfy; [defaults] may supply any of them but Ω.
struct RunKey {
  std::string_view name;
  double RunPlan::*member;
  Range range;
};

constexpr Range kAmplitude{0.0, std::numeric_limits<double>::infinity(), false, "> 0 (amplitude)"};
constexpr std::string_view kRunKeysText =
    "omega_rad_s, a, b, theta_rad, phi_rad, sample_rate_hz, duration_s";

const std::array<RunKey, 7>& RunKeys() {
  static const std::array<RunKey, 7> keys = {{
      {"omega_rad_s", &RunPlan::omega_rad_s, kAnyFinite},
      {"a", &RunPlan::a, kAmplitude},
      {"b", &RunPlan::b, kAnyFinite},
      {"theta_rad", &RunPlan::theta_rad, kAnyFinite},
      {"phi_rad", &RunPlan::phi_rad, kAnyFinite},
      {"sample_rate_hz", &RunPlan::sample_rate_hz, kPositive},
      // Bounded by the total over the runs (at most a day), checked after each run.
      {"duration_s", &RunPlan::duration_s, kPositive},
  }};
  return keys;
}

// What [defaults] supplied: a value and the node it came from (for messages about it).
struct DefaultValue {
  double value = 0.0;
  const toml::node* node = nullptr;
};
using Defaults = std::array<std::optional<DefaultValue>, 7>;

std::expected<Defaults, ConfigError> ReadDefaults(const toml::table* table, const Source& source) {
  Defaults defaults;
  if (table == nullptr) return defaults;
  TableReader reader(*table, "defaults", source);
  const auto& keys = RunKeys();
  for (std::size_t i = 1; i < keys.size(); ++i) {  // Ω is per run by nature: no default
    const toml::node* node = reader.Find(keys[i].name);
    if (node == nullptr) continue;
    auto v = NumberFrom(reader, *node, keys[i].name, keys[i].range);
    if (!v) return std::unexpected(v.error());
    defaults[i] = DefaultValue{*v, node};
  }
  if (auto unknown = reader.Unknown("a, b, theta_rad, phi_rad, sample_rate_hz, duration_s")) {
    return std::unexpected(*unknown);
  }
  return defaults;
}

std::expected<RunPlan, ConfigError> ReadRun(const toml::table& table, std::size_t index,
                                            const Defaults& defaults, const Source& source) {
  TableReader reader(table, "runs[" + std::to_string(index) + "]", source);
  RunPlan plan;
  const auto& keys = RunKeys();
  const toml::node* duration_node = nullptr;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const toml::node* node = reader.Find(keys[i].name);
    if (node != nullptr) {
      auto v = NumberFrom(reader, *node, keys[i].name, keys[i].range);
      if (!v) return std::unexpected(v.error());
      plan.*keys[i].member = *v;
    } else if (defaults[i]) {
      plan.*keys[i].member = defaults[i]->value;
      node = defaults[i]->node;
    } else {
      return std::unexpected(reader.Missing(keys[i].name, "a number, here or in [defaults]"));
    }
    if (keys[i].name == "duration_s") duration_node = node;
    if (keys[i].name == "b" && std::abs(plan.b) > plan.a) {
      ConfigError error = reader.Error(
          *node, "b", "out of range: must satisfy |b| <= a (b is the quadrature, a the amplitude)");
      return std::unexpected(error);
    }
  }
  // run_data.hpp: a run has round(duration_s · fs) samples at t = k/fs.
  const double samples = std::round(plan.duration_s * plan.sample_rate_hz);
  if (samples > kMaxSamplesPerRun || samples < 2.0) {
    return std::unexpected(reader.Error(
        *duration_node, "duration_s",
        "out of range: duration_s * sample_rate_hz gives " + config_file::CountText(samples) +
            " samples; a run needs at least 2 and at most 1e7 (a typo in a rate or a length?)"));
  }
  if (auto unknown = reader.Unknown(kRunKeysText)) return std::unexpected(*unknown);
  return plan;
}

std::expected<SimSpec, ConfigError> ReadSpec(const toml::table& root, const Source& source) {
  const std::filesystem::path& file = source.file();
  SimSpec spec;
  spec.file = file;
  TableReader reader(root, "", source);

  auto description =
      OptionalString(reader, "description", "", false, config_file::StringKind::kDescription);
  if (!description) return std::unexpected(description.error());
  spec.description = *description;

  auto session = SubTable(reader, "session", false);
  if (!session) return std::unexpected(session.error());
  spec.serial = "SIM-" + file.stem().string();
  if (*session != nullptr) {
    TableReader session_reader(**session, "session", source);
    auto serial = OptionalString(session_reader, "serial", spec.serial, true);
    if (!serial) return std::unexpected(serial.error());
    spec.serial = *serial;
    if (auto unknown = session_reader.Unknown("serial")) return std::unexpected(*unknown);
  }

  auto truth = SubTable(reader, "truth", true);
  if (!truth) return std::unexpected(truth.error());
  {
    TableReader truth_reader(**truth, "truth", source);
    auto delta = RequiredVector<6>(truth_reader, "delta", kAnyFinite);
    if (!delta) return std::unexpected(delta.error());
    spec.delta = *delta;
    // Each |ξi| < 1/4 keeps |ξ| < 1/2, which makes I + C(ξ) invertible (model.hpp).
    constexpr Range kXiRange{-0.25, 0.25, false,
                             "in (-0.25, 0.25) so that I + C(xi) is invertible"};
    auto xi = RequiredVector<4>(truth_reader, "xi", kXiRange);
    if (!xi) return std::unexpected(xi.error());
    spec.xi = *xi;
    if (auto unknown = truth_reader.Unknown("delta, xi")) return std::unexpected(*unknown);
  }

  auto noise = SubTable(reader, "noise", false);
  if (!noise) return std::unexpected(noise.error());
  if (*noise != nullptr) {
    TableReader noise_reader(**noise, "noise", source);
    auto sigma = OptionalNumber(noise_reader, "sigma", kNonNegative, 0.0);
    if (!sigma) return std::unexpected(sigma.error());
    spec.sigma = *sigma;
    if (const toml::node* seed = noise_reader.Find("seed")) {
      if (!seed->is_integer()) {
        return std::unexpected(
            noise_reader.Error(*seed, "seed", "wrong type: expected an integer"));
      }
      const std::int64_t value = seed->value<std::int64_t>().value_or(-1);
      if (value < 0) {
        return std::unexpected(noise_reader.Error(*seed, "seed", "out of range: must be >= 0"));
      }
      spec.seed = static_cast<std::uint64_t>(value);
    }
    if (auto unknown = noise_reader.Unknown("sigma, seed")) return std::unexpected(*unknown);
  }

  auto defaults_table = SubTable(reader, "defaults", false);
  if (!defaults_table) return std::unexpected(defaults_table.error());
  auto defaults = ReadDefaults(*defaults_table, source);
  if (!defaults) return std::unexpected(defaults.error());

  const toml::node* runs_node = reader.Find("runs");
  if (runs_node == nullptr)
    return std::unexpected(reader.Missing("runs", "one [[runs]] table per run"));
  const toml::array* runs = runs_node->as_array();
  if (runs == nullptr || !runs->is_array_of_tables() || runs->empty()) {
    return std::unexpected(
        reader.Error(*runs_node, "runs", "wrong type: expected one or more [[runs]] tables"));
  }
  // Checked before reading any run: 100 000 runs would otherwise all be read first.
  if (runs->size() > kMaxRuns) {
    // At the first [[runs]] header; the value (every run) is too long to quote.
    return std::unexpected(ConfigError{file, config_file::LineOf(*runs->get(0)), "runs", "",
                                       "out of range: " + std::to_string(runs->size()) +
                                           " [[runs]] tables; a spec has at most " +
                                           std::to_string(kMaxRuns)});
  }
  double total_duration_s = 0.0;
  double total_samples = 0.0;
  for (std::size_t i = 0; i < runs->size(); ++i) {
    const toml::table& table = *runs->get(i)->as_table();
    auto run = ReadRun(table, i, *defaults, source);
    if (!run) return std::unexpected(run.error());
    total_duration_s += run->duration_s;
    total_samples += std::round(run->duration_s * run->sample_rate_hz);
    if (total_duration_s > kMaxTotalFreeRunS || total_samples > kMaxTotalSamples) {
      // Named at this run's duration_s (or the default it took): the run that crossed the bound.
      const std::string run_path = "runs[" + std::to_string(i) + "]";
      const toml::node* node = table.get("duration_s");
      std::optional<TableReader> from;
      if (node != nullptr) {
        from.emplace(table, run_path, source);
      } else {
        node = (*defaults)[6]->node;
        from.emplace(**defaults_table, "defaults", source);
      }
      const std::string what = total_duration_s > kMaxTotalFreeRunS
                                   ? "runs[0.." + std::to_string(i) + "] last " +
                                         config_file::CountText(total_duration_s) +
                                         " s in total; a spec simulates at most 86400 s (a day)"
                                   : "runs[0.." + std::to_string(i) + "] have " +
                                         config_file::CountText(total_samples) +
                                         " samples in total; a spec simulates at most 1e8";
      return std::unexpected(from->Error(*node, "duration_s", "out of range: " + what));
    }
    spec.runs.push_back(*run);
  }

  if (auto unknown = reader.Unknown("description, session, truth, noise, defaults, runs")) {
    return std::unexpected(*unknown);
  }
  return spec;
}

}  // namespace

std::vector<double> SimSpec::Omegas() const {
  std::vector<double> omegas;
  omegas.reserve(runs.size());
  for (const RunPlan& run : runs) omegas.push_back(run.omega_rad_s);
  return omegas;
}

std::expected<SimSpec, ConfigError> ParseSimSpec(std::string_view toml_text,
                                                 const std::filesystem::path& file) {
  auto document = config_file::ParseTomlText(toml_text, file);
  if (!document) return std::unexpected(document.error());
  return ReadSpec(document->root, Source(file, document->text));
}

std::expected<SimSpec, ConfigError> LoadSimSpec(const std::filesystem::path& file) {
  auto document = config_file::LoadTomlFile(file);
  if (!document) return std::unexpected(document.error());
  return ReadSpec(document->root, Source(file, document->text));
}

}  // namespace hrgbench::app
