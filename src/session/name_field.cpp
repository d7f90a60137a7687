#include "name_field.hpp"

#include <cstdio>

#include "hrgbench/session/session.hpp"

namespace hrgbench::session::internal {

std::optional<std::string> NameFieldProblem(std::string_view value) {
  if (value.size() > kMaxSessionNameBytes) {
    return std::to_string(value.size()) + " bytes long (at most " +
           std::to_string(kMaxSessionNameBytes) + ")";
  }
  for (std::size_t i = 0; i < value.size(); ++i) {
    const auto c = static_cast<unsigned char>(value[i]);
    if (c < 0x20 || c == 0x7F) {
      char code[8];
      std::snprintf(code, sizeof(code), "U+%04X", c);
      return std::string("control character ") + code + " at byte " + std::to_string(i);
    }
  }
  return std::nullopt;
}

}  // namespace hrgbench::session::internal
