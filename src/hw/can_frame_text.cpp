#include "hrgbench/hw/can_frame_text.hpp"

#include <cstdint>

namespace hrgbench::hw {
namespace {

constexpr char kHex[] = "0123456789ABCDEF";
constexpr std::uint32_t kCanErrFlag = 0x20000000u;  // linux/can.h CAN_ERR_FLAG

int HexValue(char c) noexcept {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

bool ValidFdLength(std::size_t n) noexcept {
  return n <= 8 || n == 12 || n == 16 || n == 20 || n == 24 || n == 32 || n == 48 || n == 64;
}

}  // namespace

std::size_t FormatCanFrame(const CanFrame& frame, std::span<char> out) noexcept {
  // Built in a local buffer first so that a short `out` is left untouched.
  char buffer[kMaxCanFrameTextLength];
  std::size_t n = 0;
  const auto put_hex = [&](std::uint32_t value, int digits) {
    for (int d = digits - 1; d >= 0; --d) buffer[n++] = kHex[(value >> (4 * d)) & 0xFu];
  };
  if (frame.error) {
    // candump prints can_id & (CAN_ERR_MASK | CAN_ERR_FLAG): the flag makes it 2xxxxxxx.
    put_hex(kCanErrFlag | (frame.id & CanFrame::kExtendedIdMask), 8);
  } else if (frame.extended) {
    put_hex(frame.id & CanFrame::kExtendedIdMask, 8);
  } else {
    put_hex(frame.id & CanFrame::kStandardIdMask, 3);
  }
  buffer[n++] = '#';
  const bool fd = frame.fd && !frame.error;  // error frames are classic (CAN_ERR_DLC)
  const std::uint8_t max_length = fd ? CanFrame::kMaxFdLength : CanFrame::kMaxClassicLength;
  const std::uint8_t length = frame.length > max_length ? max_length : frame.length;
  if (frame.remote && !fd && !frame.error) {
    buffer[n++] = 'R';
    if (length > 0) buffer[n++] = kHex[length];
  } else {
    if (fd) {
      buffer[n++] = '#';
      buffer[n++] = frame.bit_rate_switch ? '1' : '0';
    }
    for (std::size_t i = 0; i < length; ++i) put_hex(frame.data[i], 2);
  }
  if (out.size() < n + 1) return 0;
  for (std::size_t i = 0; i < n; ++i) out[i] = buffer[i];
  out[n] = '\0';
  return n;
}

std::string CanFrameToString(const CanFrame& frame) {
  char buffer[kMaxCanFrameTextLength];
  const std::size_t n = FormatCanFrame(frame, buffer);
  return std::string(buffer, n);
}

std::optional<CanFrame> ParseCanFrame(std::string_view text) noexcept {
  const std::size_t hash = text.find('#');
  if (hash != 3 && hash != 8) return std::nullopt;
  CanFrame frame;
  frame.extended = hash == 8;
  for (std::size_t i = 0; i < hash; ++i) {
    const int v = HexValue(text[i]);
    if (v < 0) return std::nullopt;
    frame.id = (frame.id << 4) | static_cast<std::uint32_t>(v);
  }
  if ((frame.id & ~(frame.extended ? CanFrame::kExtendedIdMask : CanFrame::kStandardIdMask)) != 0) {
    return std::nullopt;
  }
  std::string_view rest = text.substr(hash + 1);
  if (!rest.empty() && (rest[0] == 'R' || rest[0] == 'r')) {
    frame.remote = true;
    if (rest.size() == 1) return frame;
    const int v = HexValue(rest[1]);
    if (rest.size() != 2 || v < 0 || v > 8) return std::nullopt;
    frame.length = static_cast<std::uint8_t>(v);
    return frame;
  }
  std::size_t max_length = CanFrame::kMaxClassicLength;
  if (!rest.empty() && rest[0] == '#') {
    if (rest.size() < 2) return std::nullopt;
    const int flags = HexValue(rest[1]);
    if (flags < 0) return std::nullopt;
    frame.fd = true;
    frame.bit_rate_switch = (flags & 1) != 0;
    max_length = CanFrame::kMaxFdLength;
    rest = rest.substr(2);
  }
  std::size_t length = 0;
  for (std::size_t i = 0; i < rest.size();) {
    if (rest[i] == '.') {
      ++i;
      continue;
    }
    if (i + 1 >= rest.size() || length >= max_length) return std::nullopt;
    const int high = HexValue(rest[i]);
    const int low = HexValue(rest[i + 1]);
    if (high < 0 || low < 0) return std::nullopt;
    frame.data[length++] = static_cast<std::uint8_t>(high * 16 + low);
    i += 2;
  }
  if (frame.fd && !ValidFdLength(length)) return std::nullopt;
  frame.length = static_cast<std::uint8_t>(length);
  return frame;
}

}  // namespace hrgbench::hw
