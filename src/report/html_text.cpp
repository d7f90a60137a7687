#include "html_text.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace hrgbench::report::internal {

std::string HtmlEscape(std::string_view text) {
  std::string out;
  out.reserve(text.size() + 16);
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      case '/': out += "&#47;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string RoundTrip(double value) {
  if (!std::isfinite(value)) return "null";
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string Readable(double value) {
  if (!std::isfinite(value)) return "\u2014";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

double Rounded(double value, int digits) {
  if (!std::isfinite(value) || value == 0.0) return value;
  char buffer[64];
  const auto result =
      std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::scientific, digits - 1);
  double out = value;
  std::from_chars(buffer, result.ptr, out);
  return out;
}

std::string ScriptSafeJson(std::string json_text) {
  std::string out;
  out.reserve(json_text.size() + json_text.size() / 16);
  for (const char c : json_text) {
    if (c == '/')
      out += "\\/";
    else if (c == '<')
      out += "\\u003c";
    else
      out += c;
  }
  return out;
}

bool ScriptSafeJavaScript(std::string* script) {
  if (script->find("</script") != std::string::npos ||
      script->find("</SCRIPT") != std::string::npos)
    return false;
  std::string out;
  out.reserve(script->size() + 64);
  std::size_t from = 0;
  for (;;) {
    const std::size_t at = script->find("://", from);
    if (at == std::string::npos) break;
    out.append(*script, from, at - from);
    out += ":\\/\\/";
    from = at + 3;
  }
  out.append(*script, from, std::string::npos);
  *script = std::move(out);
  return true;
}

}  // namespace hrgbench::report::internal
