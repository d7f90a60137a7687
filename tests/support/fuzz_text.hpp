#pragma once
// What the fuzz tests share: a portable seeded draw (the standard distributions differ between
// library versions; a seed must replay the same inputs everywhere) and the byte-level mutations
// every text format gets (flip, truncate, duplicate, delete, replace a number). Each test adds the
// mutations of its own format; each mutation appends what it did to `log`, so a failure names the
// input by seed and mutations.

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <string_view>
#include <vector>

namespace hrgbench::testing {

class Draw {
 public:
  explicit Draw(std::uint64_t seed) : engine_(seed) {}
  std::uint64_t Bits() { return engine_(); }
  std::size_t Below(std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(engine_() % n); }
  bool OneIn(std::size_t n) { return Below(n) == 0; }
  template <typename T>
  const T& Pick(const std::vector<T>& items) {
    return items[Below(items.size())];
  }

 private:
  std::mt19937_64 engine_;
};

inline void FlipByte(std::string& text, Draw& draw, std::string& log) {
  if (text.empty()) return;
  const std::size_t i = draw.Below(text.size());
  text[i] = static_cast<char>(draw.Below(256));
  log += " flip@" + std::to_string(i);
}

inline void Truncate(std::string& text, std::size_t at, std::string& log) {
  text.resize(at);
  log += " truncate@" + std::to_string(at);
}

// A copy of a span of at most `max_length` bytes inserted at `at`.
inline void DuplicateSpan(std::string& text, Draw& draw, std::size_t at, std::size_t max_length,
                          std::string& log) {
  const std::size_t from = draw.Below(text.size() + 1);
  const std::size_t length = draw.Below(std::min(text.size() - from, max_length) + 1);
  text.insert(at, text.substr(from, length));
  log += " dup[" + std::to_string(from) + "+" + std::to_string(length) + "]@" + std::to_string(at);
}

// The first number at or after `at` (digits and `number_chars`) replaced by one of `numbers`.
inline void ReplaceNumber(std::string& text, Draw& draw, std::size_t at,
                          std::string_view number_chars, const std::vector<std::string>& numbers,
                          std::string& log) {
  const std::size_t digit = text.find_first_of("0123456789", at);
  if (digit == std::string::npos) return;
  std::size_t end = digit;
  while (end < text.size() && (std::isdigit(static_cast<unsigned char>(text[end])) != 0 ||
                               number_chars.find(text[end]) != std::string_view::npos)) {
    ++end;
  }
  const std::string& number = draw.Pick(numbers);
  text.replace(digit, end - digit, number);
  log += " number@" + std::to_string(digit) + "=" + number;
}

}  // namespace hrgbench::testing
