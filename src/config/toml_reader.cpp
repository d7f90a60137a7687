#include "hrgbench/config/toml_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <system_error>
#include <utility>

#include "hrgbench/config/sha256.hpp"

namespace hrgbench::config_file {

Source::Source(std::filesystem::path file, std::string_view text)
    : file_(std::move(file)), text_(text) {}

std::string Source::Render(const toml::node& node) const {
  constexpr std::size_t kMaxShown = 80;
  const toml::source_region& region = node.source();
  std::string shown;
  if (region.begin.line == region.end.line && region.begin.line >= 1 &&
      region.end.column > region.begin.column) {
    // Find the line; only on the error path, so a scan is fine.
    std::size_t start = 0;
    for (std::size_t line = 1; line < region.begin.line && start != std::string::npos; ++line) {
      start = text_.find('\n', start);
      if (start != std::string::npos) ++start;
    }
    if (start != std::string::npos) {
      const std::size_t end = std::min(text_.find('\n', start), text_.size());
      const std::string_view line = std::string_view(text_).substr(start, end - start);
      const std::size_t begin = region.begin.column - 1;  // columns are 1-based, end exclusive
      if (begin < line.size())
        shown = std::string(line.substr(begin, region.end.column - region.begin.column));
    }
  }
  if (shown.empty()) {  // spans lines (a table, a long array): TOML's own rendering
    std::ostringstream out;
    node.visit([&out](const auto& n) { out << n; });
    shown = out.str();
  }
  if (shown.size() > kMaxShown) shown = shown.substr(0, kMaxShown) + "...";
  return shown;
}

namespace {

std::string TooLarge(std::uintmax_t bytes) {
  return "file too large: " + std::to_string(bytes) + " bytes (a config file has at most " +
         std::to_string(kMaxConfigFileBytes) + ")";
}

}  // namespace

std::expected<TomlDocument, ConfigError> ParseTomlText(std::string_view text,
                                                       const std::filesystem::path& file) {
  if (text.size() > kMaxConfigFileBytes)
    return std::unexpected(ConfigError{file, 0, "", "", TooLarge(text.size())});
  TomlDocument document;
  document.text = std::string(text);
  document.sha256_hex = Sha256Hex(text);
  try {
    document.root = toml::parse(document.text, file.string());
  } catch (const toml::parse_error& error) {
    return std::unexpected(ConfigError{file, error.source().begin.line, "", "",
                                       "TOML syntax error: " + std::string(error.description())});
  }
  return document;
}

std::expected<TomlDocument, ConfigError> LoadTomlFile(const std::filesystem::path& file) {
  // An ifstream opens a directory and reads it as empty, which then reported "missing [limits]".
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(file, ec);
  if (std::filesystem::is_directory(status))
    return std::unexpected(ConfigError{file, 0, "", "", "is a directory, not a file"});
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
    return std::unexpected(ConfigError{file, 0, "", "", "not a regular file"});
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::unexpected(ConfigError{file, 0, "", "", "cannot open the file"});
  // Read at most one byte more than allowed: enough to know the file is too large.
  std::string text(kMaxConfigFileBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) return std::unexpected(ConfigError{file, 0, "", "", "read error"});
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > kMaxConfigFileBytes) {
    const std::uintmax_t size = std::filesystem::file_size(file, ec);
    return std::unexpected(ConfigError{file, 0, "", "", TooLarge(ec ? text.size() : size)});
  }
  return ParseTomlText(text, file);
}

std::size_t LineOf(const toml::node& node) { return node.source().begin.line; }

TableReader::TableReader(const toml::table& table, std::string path, const Source& source)
    : table_(table), path_(std::move(path)), source_(source) {}

std::string TableReader::KeyPath(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

ConfigError TableReader::Error(const toml::node& node, std::string_view key,
                               std::string message) const {
  return ConfigError{source_.file(), LineOf(node), KeyPath(key), source_.Render(node),
                     std::move(message)};
}

ConfigError TableReader::Missing(std::string_view key, std::string_view what) const {
  const std::size_t line = std::max<std::size_t>(LineOf(table_), 1);
  return ConfigError{source_.file(), line, KeyPath(key), "",
                     "missing (required: " + std::string(what) + ")"};
}

const toml::node* TableReader::Find(std::string_view key) {
  read_.insert(std::string(key));
  return table_.get(key);
}

std::optional<ConfigError> TableReader::Unknown(std::string_view allowed) const {
  for (const auto& [key, node] : table_) {
    if (!read_.contains(key.str())) {
      ConfigError error =
          Error(node, key.str(), "unknown key (allowed here: " + std::string(allowed) + ")");
      // The key's own line: for a sub-table that is its [header], for a value the same line.
      if (key.source().begin.line != 0) error.line = key.source().begin.line;
      return error;
    }
  }
  return std::nullopt;
}

bool Range::Contains(double v) const {
  if (!std::isfinite(v)) return false;
  if (min_inclusive ? v < min : v <= min) return false;
  return max_inclusive ? v <= max : v < max;
}

std::expected<double, ConfigError> NumberFrom(const TableReader& reader, const toml::node& node,
                                              std::string_view key, const Range& range) {
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

std::expected<double, ConfigError> RequiredNumber(TableReader& reader, std::string_view key,
                                                  const Range& range) {
  const toml::node* node = reader.Find(key);
  if (node == nullptr)
    return std::unexpected(reader.Missing(key, "a number " + std::string(range.what)));
  return NumberFrom(reader, *node, key, range);
}

std::expected<std::optional<double>, ConfigError> MaybeNumber(TableReader& reader,
                                                              std::string_view key,
                                                              const Range& range) {
  const toml::node* node = reader.Find(key);
  if (node == nullptr) return std::optional<double>();
  auto v = NumberFrom(reader, *node, key, range);
  if (!v) return std::unexpected(v.error());
  return std::optional<double>(*v);
}

namespace {

std::expected<std::int64_t, ConfigError> IntegerFrom(const TableReader& reader,
                                                     const toml::node& node, std::string_view key,
                                                     std::int64_t min, std::int64_t max) {
  const std::string what =
      "an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  if (!node.is_integer())
    return std::unexpected(reader.Error(node, key, "wrong type: expected " + what));
  const std::int64_t v = node.value<std::int64_t>().value_or(0);
  if (v < min || v > max)
    return std::unexpected(reader.Error(node, key, "out of range: must be " + what));
  return v;
}

}  // namespace

std::expected<std::int64_t, ConfigError> OptionalInteger(TableReader& reader, std::string_view key,
                                                         std::int64_t min, std::int64_t max,
                                                         std::int64_t default_value) {
  const toml::node* node = reader.Find(key);
  if (node == nullptr) return default_value;
  return IntegerFrom(reader, *node, key, min, max);
}

std::expected<std::int64_t, ConfigError> RequiredInteger(TableReader& reader, std::string_view key,
                                                         std::int64_t min, std::int64_t max) {
  const toml::node* node = reader.Find(key);
  if (node == nullptr) {
    return std::unexpected(reader.Missing(
        key, "an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]"));
  }
  return IntegerFrom(reader, *node, key, min, max);
}

std::expected<std::optional<std::int64_t>, ConfigError> MaybeInteger(TableReader& reader,
                                                                     std::string_view key,
                                                                     std::int64_t min,
                                                                     std::int64_t max) {
  const toml::node* node = reader.Find(key);
  if (node == nullptr) return std::optional<std::int64_t>();
  auto v = IntegerFrom(reader, *node, key, min, max);
  if (!v) return std::unexpected(v.error());
  return std::optional<std::int64_t>(*v);
}

std::expected<bool, ConfigError> OptionalBool(TableReader& reader, std::string_view key,
                                              bool default_value) {
  const toml::node* node = reader.Find(key);
  if (node == nullptr) return default_value;
  if (!node->is_boolean()) {
    return std::unexpected(
        reader.Error(*node, key, "wrong type: expected a boolean (true or false)"));
  }
  return node->value<bool>().value_or(default_value);
}

std::optional<std::string> StringProblem(std::string_view value, StringKind kind) {
  const bool name = kind == StringKind::kName;
  const std::size_t max_bytes = name ? kMaxNameBytes : kMaxDescriptionBytes;
  if (value.size() > max_bytes) {
    return "out of range: " + std::to_string(value.size()) + " bytes long; " +
           (name ? "a name" : "a description") + " has at most " + std::to_string(max_bytes);
  }
  for (std::size_t i = 0; i < value.size(); ++i) {
    const auto c = static_cast<unsigned char>(value[i]);
    const bool allowed_space = !name && (c == '\t' || c == '\n');
    if ((c < 0x20 || c == 0x7F) && !allowed_space) {
      char code[8];
      std::snprintf(code, sizeof(code), "U+%04X", c);
      return std::string("out of range: control character ") + code + " at byte " +
             std::to_string(i) +
             (name ? "; a name is printable text on one line"
                   : "; a description may hold only tabs and line feeds");
    }
  }
  return std::nullopt;
}

std::expected<std::string, ConfigError> OptionalString(TableReader& reader, std::string_view key,
                                                       std::string default_value, bool non_empty,
                                                       StringKind kind) {
  const toml::node* node = reader.Find(key);
  if (node == nullptr) return default_value;
  if (!node->is_string())
    return std::unexpected(reader.Error(*node, key, "wrong type: expected a string"));
  std::string value = node->value<std::string>().value_or("");
  if (non_empty && value.empty())
    return std::unexpected(reader.Error(*node, key, "out of range: must not be empty"));
  if (auto problem = StringProblem(value, kind))
    return std::unexpected(reader.Error(*node, key, std::move(*problem)));
  return value;
}

std::expected<std::string, ConfigError> RequiredString(TableReader& reader, std::string_view key) {
  if (reader.table().get(key) == nullptr) {
    reader.Find(key);
    return std::unexpected(reader.Missing(key, "a non-empty string"));
  }
  return OptionalString(reader, key, "", true);
}

std::expected<std::size_t, ConfigError> Choice(TableReader& reader, std::string_view key,
                                               std::initializer_list<std::string_view> choices,
                                               int default_index) {
  std::string listed;
  for (std::string_view choice : choices)
    listed += (listed.empty() ? "\"" : ", \"") + std::string(choice) + "\"";
  const toml::node* node = reader.Find(key);
  if (node == nullptr) {
    if (default_index < 0) return std::unexpected(reader.Missing(key, "one of " + listed));
    return static_cast<std::size_t>(default_index);
  }
  if (!node->is_string()) {
    return std::unexpected(
        reader.Error(*node, key, "wrong type: expected a string, one of " + listed));
  }
  const std::string value = node->value<std::string>().value_or("");
  std::size_t index = 0;
  for (std::string_view choice : choices) {
    if (value == choice) return index;
    ++index;
  }
  return std::unexpected(reader.Error(*node, key, "out of range: must be one of " + listed));
}

std::expected<const toml::table*, ConfigError> SubTable(TableReader& reader, std::string_view key,
                                                        bool required) {
  const toml::node* node = reader.Find(key);
  if (node == nullptr) {
    if (required)
      return std::unexpected(reader.Missing(key, "a table [" + reader.KeyPath(key) + "]"));
    return nullptr;
  }
  if (!node->is_table()) {
    return std::unexpected(
        reader.Error(*node, key, "wrong type: expected a table [" + reader.KeyPath(key) + "]"));
  }
  return node->as_table();
}

std::optional<ConfigError> Forbid(TableReader& reader, std::string_view key,
                                  std::string_view reason) {
  const toml::node* node = reader.Find(key);
  if (node == nullptr) return std::nullopt;
  return reader.Error(*node, key, "not allowed here: " + std::string(reason));
}

}  // namespace hrgbench::config_file
