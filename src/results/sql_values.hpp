#pragma once
// Numbers to and from the text the engines exchange. Doubles go in shortest round-trip form
// (std::to_chars), so a value read back is the identical double.

#include <charconv>
#include <cstdint>
#include <optional>
#include <string>

#include "results/sql_connection.hpp"

namespace hrgbench::results::internal {

inline SqlValue Real(std::optional<double> v) {
  if (!v) return std::nullopt;
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, *v);
  if (ec != std::errc()) return std::nullopt;
  return std::string(buffer, end);
}

inline SqlValue Integer(std::int64_t v) { return std::to_string(v); }

inline std::optional<double> ToReal(const SqlValue& v) {
  if (!v) return std::nullopt;
  double out = 0.0;
  const auto [end, ec] = std::from_chars(v->data(), v->data() + v->size(), out);
  if (ec != std::errc() || end != v->data() + v->size()) return std::nullopt;
  return out;
}

inline std::int64_t ToInteger(const SqlValue& v) {
  if (!v) return 0;
  std::int64_t out = 0;
  std::from_chars(v->data(), v->data() + v->size(), out);
  return out;
}

inline std::string ToText(const SqlValue& v) { return v ? *v : std::string(); }

}  // namespace hrgbench::results::internal
