#include "hrgbench/session/number_text.hpp"

#include <charconv>

namespace hrgbench::session {

void AppendNumber(std::string& out, double value) {
  char buffer[kMaxNumberTextChars];
  // No precision argument: the shortest text that parses back to exactly `value`.
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

std::string NumberText(double value) {
  std::string text;
  AppendNumber(text, value);
  return text;
}

}  // namespace hrgbench::session
