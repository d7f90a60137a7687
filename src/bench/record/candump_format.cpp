// candump -L line formatting, after can-utils lib.c sprint_canframe() and candump.c's log line
// "(%010lu.%06lu) %s %s\n": written without printf so it is real-time safe and cheap (~100 ns).

#include <cstdint>

#include "hrgbench/bench/candump_log.hpp"

namespace hrgbench::bench {
namespace {

constexpr char kHex[] = "0123456789ABCDEF";
constexpr std::uint32_t kCanErrFlag = 0x20000000u;  // linux/can.h CAN_ERR_FLAG
constexpr std::size_t kMaxInterfaceName = 15;      // IFNAMSIZ - 1

class LineBuilder {
 public:
  explicit LineBuilder(char* buffer) : buffer_(buffer) {}
  void Put(char c) { buffer_[n_++] = c; }
  void Hex(std::uint32_t value, int digits) {
    for (int d = digits - 1; d >= 0; --d) Put(kHex[(value >> (4 * d)) & 0xFu]);
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

  const hw::CanFrame& frame = logged.frame;
  if (frame.error) {
    // candump prints can_id & (CAN_ERR_MASK | CAN_ERR_FLAG): the flag makes it 2xxxxxxx.
    line.Hex(kCanErrFlag | (frame.id & hw::CanFrame::kExtendedIdMask), 8);
  } else if (frame.extended) {
    line.Hex(frame.id & hw::CanFrame::kExtendedIdMask, 8);
  } else {
    line.Hex(frame.id & hw::CanFrame::kStandardIdMask, 3);
  }
  line.Put('#');
  const bool fd = frame.fd && !frame.error;
  const std::uint8_t max_length =
      fd ? hw::CanFrame::kMaxFdLength : hw::CanFrame::kMaxClassicLength;
  const std::uint8_t length = frame.length > max_length ? max_length : frame.length;
  if (frame.remote && !fd && !frame.error) {
    line.Put('R');
    if (length > 0) line.Put(kHex[length]);
  } else {
    if (fd) {
      line.Put('#');
      line.Put(frame.bit_rate_switch ? '1' : '0');
    }
    for (std::uint8_t i = 0; i < length; ++i) line.Hex(frame.data[i], 2);
  }
  line.Put('\n');

  const std::size_t n = line.size();
  if (out.size() < n + 1) return 0;
  for (std::size_t i = 0; i < n; ++i) out[i] = buffer[i];
  out[n] = '\0';
  return n;
}

}  // namespace hrgbench::bench
