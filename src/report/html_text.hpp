#pragma once
// Text for the page: HTML escaping, numbers for reading and for data-value, and the escaping that
// keeps inlined JSON and scripts inside their <script> element and the file free of URLs.
// Internal to src/report. Pure functions.

#include <string>
#include <string_view>

#include "hrgbench/report/html_escape.hpp"

namespace hrgbench::report::internal {

// The project's one HTML escape (hrgbench/report/html_escape.hpp).
using report::HtmlEscape;

// Shortest text that reads back to the same double (std::to_chars), "null" when not finite.
std::string RoundTrip(double value);

// For reading: 6 significant digits, "—" when not finite.
std::string Readable(double value);

// A value and its standard uncertainty written as a metrologist does: the std to two significant
// digits, the value to the same decimal place ("999.9993" and "0.0047"). Fixed notation while
// that place is between 10⁰ and 10⁻⁶ (10⁻¹² for |value| ≥ 0.01) and |value| < 10⁶; otherwise both
// in e-notation with the exponent of the larger ("0.1e4" and "1.9e4", "1.26e-5" and "0.30e-5"),
// so every digit shown is one the std allows and no more. A std that is not finite or not
// positive leaves the value at Readable precision; a value that is not finite is "—".
struct ValueWithStd {
  std::string value;
  std::string std;
};
ValueWithStd Metrological(double value, double std_dev);

// Two significant digits (a std alone); "—" when not finite.
std::string TwoSignificant(double value);

// `places` decimals in fixed notation; "—" when not finite.
std::string Fixed(double value, int places);

// Rounds to `digits` significant digits (data for charts: the page need not carry 17).
double Rounded(double value, int digits = 6);

// JSON text made safe inside <script type="application/json">: '/' → "\/" and '<' → "\u003c"
// (both only occur inside JSON strings, where these escapes mean the same characters).
std::string ScriptSafeJson(std::string json_text);

// A script made safe to inline: "://" → ":\/\/" (inside a JavaScript string, comment or regular
// expression "\/" means "/"), so the file holds no URL. False when the script contains "</script"
// (it could not be inlined).
bool ScriptSafeJavaScript(std::string* script);

}  // namespace hrgbench::report::internal
