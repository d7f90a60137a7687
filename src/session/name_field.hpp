#pragma once
// Internal: the rule for the short text fields of session.json (unit.serial, runs[].status,
// runs[].file): at most kMaxSessionNameBytes bytes, no control characters. They are printed in
// reports and warnings and used in file names, where a NUL cuts the text and a line feed forges a
// line.

#include <optional>
#include <string>
#include <string_view>

namespace hrgbench::session::internal {

// Why `value` breaks the rule ("300 bytes long ...", "control character U+0000 at byte 3"), or
// nullopt.
std::optional<std::string> NameFieldProblem(std::string_view value);

}  // namespace hrgbench::session::internal
