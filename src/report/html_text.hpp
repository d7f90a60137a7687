#pragma once
// Text for the page: HTML escaping, numbers for reading and for data-value, and the escaping that
// keeps inlined JSON and scripts inside their <script> element and the file free of URLs.
// Internal to src/report. Pure functions.

#include <string>
#include <string_view>

namespace hrgbench::report::internal {

// &, <, >, ", ' as entities, and '/' as &#47; (so no "://" can appear in the page's text).
std::string HtmlEscape(std::string_view text);

// Shortest text that reads back to the same double (std::to_chars), "null" when not finite.
std::string RoundTrip(double value);

// For reading: 6 significant digits, "—" when not finite.
std::string Readable(double value);

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
