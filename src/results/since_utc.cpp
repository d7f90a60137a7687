#include "hrgbench/results/since_utc.hpp"

#include <cctype>

namespace hrgbench::results {

std::optional<std::string> WhyNotSinceUtc(std::string_view since) {
  // The shape of "2026-11-23T14:05:00Z": each position a digit or its separator; any prefix that
  // ends after a whole field is a time (the Z only after the seconds).
  constexpr std::string_view kShape = "dddd-dd-ddTdd:dd:ddZ";
  bool shaped = !since.empty() && since.size() <= kShape.size();
  for (std::size_t i = 0; shaped && i < since.size(); ++i) {
    const char c = since[i];
    shaped = kShape[i] == 'd' ? std::isdigit(static_cast<unsigned char>(c)) != 0 : c == kShape[i];
  }
  const std::size_t n = since.size();
  const bool whole_field = n == 4 || n == 7 || n == 10 || n == 13 || n == 16 || n == 19 || n == 20;
  if (shaped && whole_field) return std::nullopt;
  return "'" + std::string(since) +
         "' is not a UTC time in ISO 8601 or a prefix of one (2026, 2026-11, 2026-11-23, "
         "2026-11-23T14:05, 2026-11-23T14:05:00Z)";
}

std::string SinceLowerBound(std::string_view since) {
  constexpr std::string_view kEarliest = "0000-01-01T00:00:00.000000Z";
  const std::string_view given = since.ends_with('Z') ? since.substr(0, since.size() - 1) : since;
  if (given.size() >= kEarliest.size()) return std::string(since);
  return std::string(given) + std::string(kEarliest.substr(given.size()));
}

}  // namespace hrgbench::results
