// candump -L line formatting, after candump.c's log line "(%010lu.%06lu) %s %s\n": written without
// printf so it is real-time safe and cheap (~100 ns). The frame itself is the hardware layer's
// can-utils notation (hw::FormatCanFrame, after can-utils lib.c sprint_canframe()).

#include <cstdint>

#include "hrgbench/hw/can_frame_text.hpp"
#include "hrgbench/session/candump_log.hpp"

namespace hrgbench::bench {
namespace {

constexpr std::size_t kMaxInterfaceName = 15;  // IFNAMSIZ - 1

class LineBuilder {
 public:
  explicit LineBuilder(char* buffer) : buffer_(buffer) {}
  void Put(char c) { buffer_[n_++] = c; }
  // The frame's can-utils text (and a NUL the next Put overwrites); `capacity` is the whole
  // buffer's size. False if it did not fit, which kMaxCandumpLineLength rules out.
  bool Frame(const hw::CanFrame& frame, std::size_t capacity) {
    const std::size_t written = hw::FormatCanFrame(frame, std::span(buffer_ + n_, capacity - n_));
    n_ += written;
    return written > 0;
  }
  // Zero-padded to at least `min_digits` decimal digits.
  void Decimal(std::uint64_t value, int min_digits) {
    char digits[20];
    int count = 0;
    do {
      digits[count++] = static_cast<char>('0' + value % 10);
      value /= 10;
    } while (value != 0);
    for (int i = count; i < min_digits; ++i) Put('0');
    while (count > 0) Put(digits[--count]);
  }
  std::size_t size() const { return n_; }

 private:
  char* buffer_;
  std::size_t n_ = 0;
};

}  // namespace

std::size_t FormatCandumpLine(const LoggedCanFrame& logged, std::string_view interface_name,
                              std::span<char> out) noexcept {
  if (interface_name.empty() || interface_name.size() > kMaxInterfaceName) return 0;
  for (const char c : interface_name) {
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\0') return 0;
  }
  char buffer[kMaxCandumpLineLength];
  LineBuilder line(buffer);
  const std::int64_t t_ns = logged.unix_time_ns < 0 ? 0 : logged.unix_time_ns;
  line.Put('(');
  line.Decimal(static_cast<std::uint64_t>(t_ns / 1'000'000'000), 10);
  line.Put('.');
  line.Decimal(static_cast<std::uint64_t>(t_ns % 1'000'000'000 / 1000), 6);
  line.Put(')');
  line.Put(' ');
  for (const char c : interface_name) line.Put(c);
  line.Put(' ');

  if (!line.Frame(logged.frame, sizeof buffer)) return 0;
  line.Put('\n');

  const std::size_t n = line.size();
  if (out.size() < n + 1) return 0;
  for (std::size_t i = 0; i < n; ++i) out[i] = buffer[i];
  out[n] = '\0';
  return n;
}

}  // namespace hrgbench::bench
