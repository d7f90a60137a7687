#pragma once
// The nesting depth of JSON text, found without parsing it. nlohmann::json parses,
// copies, prints and destroys recursively, one stack frame per level, so a document nested 100 000
// deep overflows the stack (signal 11) before any check on the parsed value can run: every reader
// of a JSON file from outside (session.json, tune.json) asks this first.

#include <cstddef>
#include <optional>
#include <string_view>

namespace hrgbench::session {

struct JsonDepthExcess {
  std::size_t line = 0;   // 1-based line of the bracket that opens level max_depth + 1
  std::size_t depth = 0;  // max_depth + 1
};

// Where `text` first nests arrays and objects deeper than `max_depth`, or nullopt. Counts '[' and
// '{' outside strings (backslash escapes honoured); reads any text, valid JSON or not, in one pass
// with no allocation.
std::optional<JsonDepthExcess> FindJsonDepthExcess(std::string_view text, std::size_t max_depth);

}  // namespace hrgbench::session
