#pragma once
// Test-side reader of candump -L log lines, written from can-utils lib.c parse_canframe()'s rules
// (independently of src/session's candump formatter, so a round trip checks one against the other):
//   "(<sec>.<usec>) <ifname> <frame>" with <frame> one of
//   3 hex digits '#' data | 8 hex digits '#' data (extended, or error frame when 0x20000000 set)
//   <id>#R[<len>] | <id>##<flags nibble><data>. Data bytes may be separated by '.'.

#include <cstdint>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hrgbench/hw/can_frame.hpp"

namespace hrgbench::testing {

struct CandumpLine {
  std::int64_t unix_time_ns = 0;  // microsecond resolution, as the log holds it
  std::string interface_name;
  hw::CanFrame frame;
};

namespace candump_detail {
inline int Nibble(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}
inline bool AllDigits(std::string_view s) {
  if (s.empty()) return false;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
  }
  return true;
}
}  // namespace candump_detail

inline std::optional<CandumpLine> ParseCandumpLine(std::string_view line) {
  using candump_detail::Nibble;
  if (!line.empty() && line.back() == '\n') line.remove_suffix(1);
  if (line.size() < 4 || line[0] != '(') return std::nullopt;
  const std::size_t close = line.find(") ");
  if (close == std::string_view::npos) return std::nullopt;
  const std::string_view stamp = line.substr(1, close - 1);
  const std::size_t dot = stamp.find('.');
  if (dot == std::string_view::npos || stamp.size() - dot - 1 != 6) return std::nullopt;
  if (!candump_detail::AllDigits(stamp.substr(0, dot)) ||
      !candump_detail::AllDigits(stamp.substr(dot + 1))) {
    return std::nullopt;
  }
  CandumpLine out;
  out.unix_time_ns = std::stoll(std::string(stamp.substr(0, dot))) * 1'000'000'000 +
                     std::stoll(std::string(stamp.substr(dot + 1))) * 1000;
  std::string_view rest = line.substr(close + 2);
  const std::size_t space = rest.find(' ');
  if (space == 0 || space == std::string_view::npos) return std::nullopt;
  out.interface_name = std::string(rest.substr(0, space));
  std::string_view text = rest.substr(space + 1);

  hw::CanFrame& frame = out.frame;
  std::size_t idx = 0;
  if (text.size() >= 4 && text[3] == '#') {
    idx = 3;
  } else if (text.size() >= 9 && text[8] == '#') {
    idx = 8;
  } else {
    return std::nullopt;
  }
  std::uint32_t id = 0;
  for (std::size_t i = 0; i < idx; ++i) {
    const int v = Nibble(text[i]);
    if (v < 0) return std::nullopt;
    id = (id << 4) | static_cast<std::uint32_t>(v);
  }
  if (idx == 8) {
    if (id & 0x20000000u) {
      frame.error = true;
      id &= 0x1FFFFFFFu;
    } else {
      frame.extended = true;
    }
  }
  frame.id = id;
  text = text.substr(idx + 1);
  if (!text.empty() && (text[0] == 'R' || text[0] == 'r')) {
    frame.remote = true;
    if (text.size() == 2) {
      const int v = Nibble(text[1]);
      if (v < 0 || v > 8) return std::nullopt;
      frame.length = static_cast<std::uint8_t>(v);
    } else if (text.size() != 1) {
      return std::nullopt;
    }
    return out;
  }
  std::size_t max_length = 8;
  if (!text.empty() && text[0] == '#') {
    if (text.size() < 2 || Nibble(text[1]) < 0) return std::nullopt;
    frame.fd = true;
    frame.bit_rate_switch = (Nibble(text[1]) & 1) != 0;
    max_length = 64;
    text = text.substr(2);
  }
  std::size_t length = 0;
  for (std::size_t i = 0; i < text.size();) {
    if (text[i] == '.') {
      ++i;
      continue;
    }
    if (i + 1 >= text.size() || length >= max_length) return std::nullopt;
    const int high = Nibble(text[i]);
    const int low = Nibble(text[i + 1]);
    if (high < 0 || low < 0) return std::nullopt;
    frame.data[length++] = static_cast<std::uint8_t>(high * 16 + low);
    i += 2;
  }
  frame.length = static_cast<std::uint8_t>(length);
  return out;
}

// Every line of a log file; a line that does not parse makes the whole result nullopt.
inline std::optional<std::vector<CandumpLine>> ReadCandumpLog(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  std::vector<CandumpLine> lines;
  for (std::string line; std::getline(in, line);) {
    auto parsed = ParseCandumpLine(line);
    if (!parsed) return std::nullopt;
    lines.push_back(std::move(*parsed));
  }
  return lines;
}

}  // namespace hrgbench::testing
