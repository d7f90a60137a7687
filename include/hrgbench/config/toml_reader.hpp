#pragma once
// Strict reading of TOML config files (STYLE rule 10), shared by every loader in the project: the
// bench's station, sequence and limits files (src/bench/config), the simulation specs (src/app)
// and hrg-gyro-sim's config file (drivers/sim/gyro_sim_config.cpp).
//
// Strict means: a key nobody asked for is an error (TableReader::Unknown), a value of the wrong
// type or outside its range is an error, and every error is a ConfigError naming the file, the
// line, the key as a dotted path and the value exactly as written. Integers are accepted where a
// number is expected ("sigma = 0"); numbers are not accepted where an integer is ("port = 502.0" is
// an error, because a fractional port, id or count is always a typo).
//
// Not thread-safe per object; no global state. Not for real-time code (allocates, parses).

#include <toml++/toml.h>

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <expected>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>

#include "hrgbench/config/config_bounds.hpp"
#include "hrgbench/config/config_error.hpp"

// Loader shorthand: `HRG_TRY(v, Expr());` declares v = Expr() and returns its error from the
// enclosing function (whose return type is a std::expected<_, ConfigError>) when it has one;
// `HRG_CHECK(Unknown(...));` returns the error an optional<ConfigError> holds. A loader is a long
// list of reads, and without these every read is three lines of which two are the same.
#define HRG_TRY(var, expr) \
  auto var = (expr);       \
  if (!var) return std::unexpected(std::move(var).error())
#define HRG_CHECK(opt_error) \
  if (auto hrg_error_ = (opt_error)) return std::unexpected(std::move(*hrg_error_))

namespace hrgbench::config_file {

// The file's text, kept so that messages quote a value exactly as the user wrote it ("0.3", not the
// "0.29999999999999999" a re-print of the double gives). Owns a copy: safe to move.
class Source {
 public:
  Source(std::filesystem::path file, std::string_view text);

  const std::filesystem::path& file() const { return file_; }
  // The node's text as written (cut to 80 characters), or TOML's rendering when it spans lines.
  std::string Render(const toml::node& node) const;

 private:
  std::filesystem::path file_;
  std::string text_;
};

// A parsed file: its exact bytes, their SHA-256 (the config hash recorded in sessions), the tree.
struct TomlDocument {
  std::string text;
  std::string sha256_hex;
  toml::table root;
};

// Reads `file` (errors at line 0: cannot open, a directory or not a regular file, larger than
// kMaxConfigFileBytes, read error) and parses it (error: TOML syntax error at its line).
std::expected<TomlDocument, ConfigError> LoadTomlFile(const std::filesystem::path& file);
// The same from text already in memory (also refused above kMaxConfigFileBytes); `file` is only
// used in messages.
std::expected<TomlDocument, ConfigError> ParseTomlText(std::string_view text,
                                                       const std::filesystem::path& file);

std::size_t LineOf(const toml::node& node);

// Reads one table: hands out its keys, remembers which were read, and reports the rest as unknown.
class TableReader {
 public:
  // `path` is the table's dotted path ("" for the root); `source` must outlive the reader.
  TableReader(const toml::table& table, std::string path, const Source& source);

  std::string KeyPath(std::string_view key) const;
  const Source& source() const { return source_; }
  const toml::table& table() const { return table_; }

  // An error about the value of `key` (its line, its text).
  ConfigError Error(const toml::node& node, std::string_view key, std::string message) const;
  // A required key is absent: reported at the table's [header] line (line 1 for the root).
  ConfigError Missing(std::string_view key, std::string_view what) const;

  // The node of `key` or nullptr; marks the key as known either way.
  const toml::node* Find(std::string_view key);

  // The first key that was never asked for, as an error listing what is allowed here.
  std::optional<ConfigError> Unknown(std::string_view allowed) const;

 private:
  const toml::table& table_;
  std::string path_;
  const Source& source_;
  std::set<std::string, std::less<>> read_;
};

// A range check on a finite number; `what` completes "must be ...".
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_inclusive = true;
  std::string_view what = "a finite number";
  bool max_inclusive = true;

  bool Contains(double v) const;
};

inline constexpr Range kAnyFinite{};
inline constexpr Range kPositive{0.0, std::numeric_limits<double>::infinity(), false, "> 0"};
inline constexpr Range kNonNegative{0.0, std::numeric_limits<double>::infinity(), true, ">= 0"};

// Numbers (TOML integer or float) checked against `range`.
std::expected<double, ConfigError> NumberFrom(const TableReader& reader, const toml::node& node,
                                              std::string_view key, const Range& range);
std::expected<double, ConfigError> OptionalNumber(TableReader& reader, std::string_view key,
                                                  const Range& range, double default_value);
std::expected<double, ConfigError> RequiredNumber(TableReader& reader, std::string_view key,
                                                  const Range& range);
// Absent → std::nullopt (a key whose absence means "not set", e.g. an optional limit).
std::expected<std::optional<double>, ConfigError> MaybeNumber(TableReader& reader,
                                                              std::string_view key,
                                                              const Range& range);

// TOML integers only, in [min, max].
std::expected<std::int64_t, ConfigError> OptionalInteger(TableReader& reader, std::string_view key,
                                                         std::int64_t min, std::int64_t max,
                                                         std::int64_t default_value);
std::expected<std::int64_t, ConfigError> RequiredInteger(TableReader& reader, std::string_view key,
                                                         std::int64_t min, std::int64_t max);
std::expected<std::optional<std::int64_t>, ConfigError> MaybeInteger(TableReader& reader,
                                                                     std::string_view key,
                                                                     std::int64_t min,
                                                                     std::int64_t max);

std::expected<bool, ConfigError> OptionalBool(TableReader& reader, std::string_view key,
                                              bool default_value);

// What a string may hold (config_bounds.hpp): a name is printable text of at most kMaxNameBytes
// bytes; a description may also hold tabs and line feeds, up to kMaxDescriptionBytes.
enum class StringKind { kName, kDescription };

// Why `value` is not a valid string of `kind` ("out of range: ..."), or nullopt.
std::optional<std::string> StringProblem(std::string_view value, StringKind kind);

std::expected<std::string, ConfigError> OptionalString(TableReader& reader, std::string_view key,
                                                       std::string default_value, bool non_empty,
                                                       StringKind kind = StringKind::kName);
// A non-empty name.
std::expected<std::string, ConfigError> RequiredString(TableReader& reader, std::string_view key);

// A string that must be one of `choices`; returns its index. `default_index` < 0: required.
std::expected<std::size_t, ConfigError> Choice(TableReader& reader, std::string_view key,
                                               std::initializer_list<std::string_view> choices,
                                               int default_index);

// A sub-table; nullptr when absent and optional.
std::expected<const toml::table*, ConfigError> SubTable(TableReader& reader, std::string_view key,
                                                        bool required);

// An error when `key` is present: for keys that do not apply in this context ("only with
// kind = \"real\""). Marks the key as known so that it is not also reported as unknown.
std::optional<ConfigError> Forbid(TableReader& reader, std::string_view key,
                                  std::string_view reason);

// An array of N numbers, each in `range`; element errors name "key[i]".
template <int N>
std::expected<Eigen::Matrix<double, N, 1>, ConfigError> VectorFrom(const TableReader& reader,
                                                                   const toml::node& node,
                                                                   std::string_view key,
                                                                   const Range& range) {
  const std::string what = "an array of " + std::to_string(N) + " numbers";
  const toml::array* array = node.as_array();
  if (array == nullptr)
    return std::unexpected(reader.Error(node, key, "wrong type: expected " + what));
  if (array->size() != static_cast<std::size_t>(N)) {
    return std::unexpected(reader.Error(
        node, key, "wrong length " + std::to_string(array->size()) + ": expected " + what));
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

template <int N>
std::expected<Eigen::Matrix<double, N, 1>, ConfigError> RequiredVector(TableReader& reader,
                                                                       std::string_view key,
                                                                       const Range& range) {
  const toml::node* node = reader.Find(key);
  if (node == nullptr) {
    return std::unexpected(reader.Missing(key, "an array of " + std::to_string(N) + " numbers"));
  }
  return VectorFrom<N>(reader, *node, key, range);
}

}  // namespace hrgbench::config_file
