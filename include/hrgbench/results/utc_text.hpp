#pragma once
// The one text form of a time in the results store: "2026-11-23T19:18:19.582862Z" (UTC, six
// fraction digits, always). SQLite stores it as this text, so text order is time order ("…:00Z"
// sorted before "…:00.5Z" would not be); PostgreSQL stores a timestamptz and reads it back as this
// text (results_queries.cpp), so the two engines answer identically. Microseconds are what
// PostgreSQL keeps: finer digits are cut, as the bench never writes them.
//
// Pure string work; thread-safe; never throws (except std::bad_alloc).

#include <optional>
#include <string>
#include <string_view>

namespace hrgbench::results {

// `iso` ("YYYY-MM-DDTHH:MM:SS", an optional fraction, then Z or ±HH:MM) as the canonical UTC text;
// nullopt when it is not such a time (a field out of range included).
std::optional<std::string> CanonicalUtc(std::string_view iso);

}  // namespace hrgbench::results
