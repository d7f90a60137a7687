#pragma once
// How the session format writes a number: the shortest text that reads back to exactly the same
// double (std::to_chars without a precision), so a value written and read again is bit-identical.
// The run CSV writer (session::WriteRunCsv) and the bench's streaming run writer must produce the
// same bytes for the same samples, and messages that quote a value show it as it is stored: all of
// them use these.
//
// Thread-safe, no locale, never throws except std::bad_alloc (AppendNumber: not even that when
// `out` has the capacity).

#include <cstddef>
#include <string>

namespace hrgbench::session {

// Longest such text: "-2.2250738585072014e-308" is 24 characters.
inline constexpr std::size_t kMaxNumberTextChars = 32;

void AppendNumber(std::string& out, double value);
std::string NumberText(double value);

}  // namespace hrgbench::session
