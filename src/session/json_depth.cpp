#include "hrgbench/session/json_depth.hpp"

namespace hrgbench::session {

std::optional<JsonDepthExcess> FindJsonDepthExcess(std::string_view text, std::size_t max_depth) {
  std::size_t depth = 0;
  std::size_t line = 1;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') ++line;
    if (in_string) {
      if (c == '\\') {
        ++i;  // the escaped character cannot end the string
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) return JsonDepthExcess{line, depth};
    } else if ((c == ']' || c == '}') && depth > 0) {
      // Unbalanced closers are the parser's to report; they must not hide a later excess.
      --depth;
    }
  }
  return std::nullopt;
}

}  // namespace hrgbench::session
