#pragma once
// The project's one HTML escape, for every page it writes (the session report, the line view of
// hrg-results serve): text and attribute values both. Pure, thread-safe.

#include <string>
#include <string_view>

namespace hrgbench::report {

// &, <, >, ", ' as entities, and '/' as &#47; (so no "://" appears in a page's text or attributes:
// the report's file must hold no URL, and a browser shows the same characters).
std::string HtmlEscape(std::string_view text);

}  // namespace hrgbench::report
