#include "html_text.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace hrgbench::report::internal {
namespace {
constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();
}  // namespace

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

ValueWithStd Metrological(double value, double std_dev) {
  if (!std::isfinite(std_dev) || std_dev <= 0.0) return {Readable(value), Readable(std_dev)};
  // The decade of the std's first digit, after rounding to two digits (9.96 rounds to 10).
  int e = static_cast<int>(std::floor(std::log10(std_dev)));
  if (std::round(std_dev / std::pow(10.0, e - 1)) >= 100.0) ++e;
  const int decimals = 1 - e;
  const bool value_ok = std::isfinite(value);
  const double magnitude = value_ok ? std::abs(value) : 0.0;
  const bool fixed =
      magnitude < 1e6 && decimals >= 0 && (decimals <= 6 || (decimals <= 12 && magnitude >= 0.01));
  char buffer[64];
  const auto text = [&](double v, int places, const char* suffix) {
    std::snprintf(buffer, sizeof buffer, "%.*f%s", places, v, suffix);
    std::string out = buffer;
    // "-0.000": the value rounds to zero at this precision; the sign says nothing.
    const std::string mantissa = out.substr(0, out.find('e'));
    if (out.front() == '-' && mantissa.find_first_of("123456789") == std::string::npos)
      out.erase(0, 1);
    return out;
  };
  if (fixed)
    return {value_ok ? text(value, decimals, "") : Readable(value), text(std_dev, decimals, "")};
  int big = e;
  if (value_ok && magnitude > 0.0)
    big = std::max(e, static_cast<int>(std::floor(std::log10(magnitude))));
  const int places = big - e + 1;
  const std::string exponent = "e" + std::to_string(big);
  const double scale = std::pow(10.0, big);
  return {value_ok ? text(value / scale, places, exponent.c_str()) : Readable(value),
          text(std_dev / scale, places, exponent.c_str())};
}

std::string TwoSignificant(double value) {
  if (!std::isfinite(value)) return "\u2014";
  if (value > 0.0) return Metrological(kNoValue, value).std;
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.2g", value);
  return buffer;
}

std::string Fixed(double value, int places) {
  if (!std::isfinite(value)) return "\u2014";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", places, value);
  return buffer;
}

double Rounded(double value, int digits) {
  if (!std::isfinite(value) || value == 0.0) return value;
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value,
                                    std::chars_format::scientific, digits - 1);
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
