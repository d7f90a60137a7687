#pragma once
// The time a session filter starts from (`hrg-results ... --since T`, SessionFilter::since_utc).
// The store compares it with each session's started_utc ("2026-11-23T14:05:00Z") as text, which is
// right for an ISO 8601 UTC time or a prefix of one ("2026", "2026-11", "2026-11-23",
// "2026-11-23T14", "2026-11-23T14:05", "2026-11-23T14:05:00Z") and silently wrong for anything
// else ("yesterday" sorts after every digit: 0 rows). So anything else is refused. Thread-safe.

#include <optional>
#include <string>
#include <string_view>

namespace hrgbench::results {

// Why `since` is not such a time ("'yesterday' is not a UTC time in ISO 8601 ..."), or none.
std::optional<std::string> WhyNotSinceUtc(std::string_view since);

// The first instant `since` (one WhyNotSinceUtc accepts) names, in the store's canonical text
// (utc_text.hpp): "2026-11" → "2026-11-01T00:00:00.000000Z". PostgreSQL compares it as a
// timestamptz, SQLite as text; both give the same sessions.
std::string SinceLowerBound(std::string_view since);

}  // namespace hrgbench::results
