#include <toml++/toml.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <utility>

#include "app/sim_spec.hpp"

namespace hrgbench::app {
namespace {

using estimator::RunPlan;

// The spec's text, kept so that messages quote a value exactly as the user wrote it ("0.3", not the
// "0.29999999999999999" a re-print of the double gives).
struct Source {
  std::filesystem::path file;
  std::vector<std::string_view> lines;  // into the text passed to ParseSimSpec

  Source(const std::filesystem::path& path, std::string_view text) : file(path) {
    std::size_t start = 0;
    while (start <= text.size()) {
      const std::size_t end = std::min(text.find('\n', start), text.size());
      lines.push_back(text.substr(start, end - start));
      start = end + 1;
    }
  }

  std::string Render(const toml::node& node) const {
    constexpr std::size_t kMaxShown = 80;
    const toml::source_region& region = node.source();
    std::string text;
    if (region.begin.line == region.end.line && region.begin.line >= 1 &&
        region.begin.line <= lines.size() && region.end.column > region.begin.column) {
      const std::string_view line = lines[region.begin.line - 1];
      const std::size_t begin = region.begin.column - 1;  // columns are 1-based, end exclusive
      if (begin < line.size())
        text = std::string(line.substr(begin, region.end.column - region.begin.column));
    }
    if (text.empty()) {  // spans lines (a table, a long array): TOML's own rendering
      std::ostringstream out;
      node.visit([&out](const auto& n) { out << n; });
      text = out.str();
    }
    if (text.size() > kMaxShown) text = text.substr(0, kMaxShown) + "...";
    return text;
  }
};

std::size_t LineOf(const toml::node& node) { return node.source().begin.line; }

// Reads one table: hands out its keys, remembers which were read, and reports the rest as unknown.
// Errors are collected as the first one found (the loader stops at the first error; a user fixes
// one line at a time, and a later error may be a consequence of an earlier one).
class TableReader {
 public:
  TableReader(const toml::table& table, std::string path, const Source& source)
      : table_(table), path_(std::move(path)), source_(source) {}

  std::string KeyPath(std::string_view key) const {
    return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
  }

  ConfigError Error(const toml::node& node, std::string_view key, std::string message) const {
    return ConfigError{source_.file, LineOf(node), KeyPath(key), source_.Render(node),
                       std::move(message)};
  }

  ConfigError Missing(std::string_view key, std::string_view what) const {
    // The table's own line: its [header], or line 1 for the root table (which has no header).
    const std::size_t line = std::max<std::size_t>(LineOf(table_), 1);
    return ConfigError{source_.file, line, KeyPath(key), "",
                       "missing (required: " + std::string(what) + ")"};
  }

  const toml::node* Find(std::string_view key) {
    read_.insert(std::string(key));
    return table_.get(key);
  }

  // The first key that was never asked for, as an error.
  std::optional<ConfigError> Unknown(std::string_view allowed) const {
    for (const auto& [key, node] : table_) {
      if (!read_.contains(std::string(key.str()))) {
        ConfigError error =
            Error(node, key.str(), "unknown key (allowed here: " + std::string(allowed) + ")");
        error.line = key.source().begin.line != 0 ? key.source().begin.line : error.line;
        return error;
      }
    }
    return std::nullopt;
  }

 private:
  const toml::table& table_;
  std::string path_;
  const Source& source_;
  std::set<std::string> read_;
};

// A range check on a finite number; `what` completes "must be ...".
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_inclusive = true;
  std::string_view what = "a finite number";

  bool Contains(double v) const {
    if (!std::isfinite(v)) return false;
    if (min_inclusive ? v < min : v <= min) return false;
    return v <= max;
  }
};

constexpr Range kAnyFinite{};
constexpr Range kPositive{0.0, std::numeric_limits<double>::infinity(), false, "> 0"};
constexpr Range kNonNegative{0.0, std::numeric_limits<double>::infinity(), true, ">= 0"};

std::expected<double, ConfigError> NumberFrom(const TableReader& reader, const toml::node& node,
                                              std::string_view key, const Range& range) {
  // Integers are accepted where a number is expected: "sigma = 0" means 0.0.
  const std::optional<double> v = node.is_number() ? node.value<double>() : std::nullopt;
  if (!v) {
    return std::unexpected(
        reader.Error(node, key, "wrong type: expected a number (" + std::string(range.what) + ")"));
  }
  if (!range.Contains(*v)) {
    return std::unexpected(
        reader.Error(node, key, "out of range: must be " + std::string(range.what)));
  }
  return *v;
}

std::expected<double, ConfigError> OptionalNumber(TableReader& reader, std::string_view key,
                                                  const Range& range, double default_value) {
  const toml::node* node = reader.Find(key);
  if (node == nullptr) return default_value;
  return NumberFrom(reader, *node, key, range);
}

template <int N>
std::expected<Eigen::Matrix<double, N, 1>, ConfigError> RequiredVector(TableReader& reader,
                                                                       std::string_view key,
                                                                       const Range& range) {
  const std::string what = "an array of " + std::to_string(N) + " numbers";
  const toml::node* node = reader.Find(key);
  if (node == nullptr) return std::unexpected(reader.Missing(key, what));
  const toml::array* array = node->as_array();
  if (array == nullptr)
    return std::unexpected(reader.Error(*node, key, "wrong type: expected " + what));
  if (array->size() != static_cast<std::size_t>(N)) {
    return std::unexpected(reader.Error(
        *node, key, "wrong length " + std::to_string(array->size()) + ": expected " + what));
  }
  Eigen::Matrix<double, N, 1> out;
  for (int i = 0; i < N; ++i) {
    const toml::node& element = *array->get(static_cast<std::size_t>(i));
    const std::string element_key = std::string(key) + "[" + std::to_string(i) + "]";
    auto v = NumberFrom(reader, element, element_key, range);
    if (!v) return std::unexpected(v.error());
    out(i) = *v;
  }
  return out;
}

// A sub-table; nullptr when absent and optional.
std::expected<const toml::table*, ConfigError> SubTable(TableReader& reader, std::string_view key,
                                                        bool required) {
  const toml::node* node = reader.Find(key);
  if (node == nullptr) {
    if (required) return std::unexpected(reader.Missing(key, "a table [" + std::string(key) + "]"));
    return nullptr;
  }
  if (!node->is_table()) {
    return std::unexpected(
        reader.Error(*node, key, "wrong type: expected a table [" + std::string(key) + "]"));
  }
  return node->as_table();
}

std::expected<std::string, ConfigError> OptionalString(TableReader& reader, std::string_view key,
                                                       std::string default_value, bool non_empty) {
  const toml::node* node = reader.Find(key);
  if (node == nullptr) return default_value;
  if (!node->is_string())
    return std::unexpected(reader.Error(*node, key, "wrong type: expected a string"));
  std::string value = node->value<std::string>().value_or("");
  if (non_empty && value.empty()) {
    return std::unexpected(reader.Error(*node, key, "out of range: must not be empty"));
  }
  return value;
}

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
        "out of range: duration_s * sample_rate_hz gives " +
            std::to_string(static_cast<long long>(samples)) +
            " samples; a run needs at least 2 and at most 1e7 (a typo in a rate or a length?)"));
  }
  if (auto unknown = reader.Unknown(kRunKeysText)) return std::unexpected(*unknown);
  return plan;
}

std::expected<SimSpec, ConfigError> ReadSpec(const toml::table& root, const Source& source) {
  const std::filesystem::path& file = source.file;
  SimSpec spec;
  spec.file = file;
  TableReader reader(root, "", source);

  auto description = OptionalString(reader, "description", "", false);
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
  for (std::size_t i = 0; i < runs->size(); ++i) {
    auto run = ReadRun(*runs->get(i)->as_table(), i, *defaults, source);
    if (!run) return std::unexpected(run.error());
    spec.runs.push_back(*run);
  }

  if (auto unknown = reader.Unknown("description, session, truth, noise, defaults, runs")) {
    return std::unexpected(*unknown);
  }
  return spec;
}

}  // namespace

std::string ConfigError::ToString() const {
  std::string text = file.string();
  if (line != 0) text += ":" + std::to_string(line);
  text += ": ";
  if (!key.empty()) {
    text += "key '" + key + "'";
    if (!value.empty()) text += " = " + value;
    text += ": ";
  }
  return text + message;
}

std::vector<double> SimSpec::Omegas() const {
  std::vector<double> omegas;
  omegas.reserve(runs.size());
  for (const RunPlan& run : runs) omegas.push_back(run.omega_rad_s);
  return omegas;
}

std::expected<SimSpec, ConfigError> ParseSimSpec(std::string_view toml_text,
                                                 const std::filesystem::path& file) {
  try {
    const toml::table root = toml::parse(toml_text, file.string());
    return ReadSpec(root, Source(file, toml_text));
  } catch (const toml::parse_error& error) {
    return std::unexpected(ConfigError{file, error.source().begin.line, "", "",
                                       "TOML syntax error: " + std::string(error.description())});
  }
}

std::expected<SimSpec, ConfigError> LoadSimSpec(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::unexpected(ConfigError{file, 0, "", "", "cannot open the file"});
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return std::unexpected(ConfigError{file, 0, "", "", "read error"});
  return ParseSimSpec(text.str(), file);
}

}  // namespace hrgbench::app
