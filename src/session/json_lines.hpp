#pragma once
// Internal: line numbers for JSON errors. nlohmann::json (3.11) keeps no source positions, so when
// a key is missing or has the wrong type we scan the text again to find where it is.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace hrgbench::session::internal {

// 1-based line of the value at `path` in `text` (valid JSON): "" is the root, "unit.serial" an
// object member, "runs[2].id" an array element (0-based). 0 when there is no such value.
std::size_t JsonValueLine(std::string_view text, std::string_view path);

struct JsonScalarHit {
  std::size_t line = 0;
  std::string path;
};

// The first non-string scalar whose source text is exactly `token` (e.g. "1e999"): nlohmann reports
// a number overflow with the token but no position.
std::optional<JsonScalarHit> FindJsonScalar(std::string_view text, std::string_view token);

// 1-based line of the byte at 0-based `offset` (clamped to the text).
std::size_t LineOfOffset(std::string_view text, std::size_t offset);

}  // namespace hrgbench::session::internal
