#pragma once
// CAN frames in can-utils notation (cansend / candump, STYLE rule 7), for golden-frame tests and
// logs, so that a frame in a failure message can be pasted into `cansend`:
//   123#DEADBEEF        standard id (3 hex digits), classic data
//   1ABCDEF0#00         extended id (8 hex digits)
//   123#R  123#R4       remote frame, optional length
//   123##1DEADBEEF      CAN FD: '##', one flags nibble (1 = BRS, 2 = ESI; ESI is ignored), data
// Data may contain '.' between bytes (cansend accepts 11.22.33). Hex digits in either case;
// formatting writes upper case without dots, as candump does.

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "hrgbench/hw/can_frame.hpp"

namespace hrgbench::hw {

// Longest text FormatCanFrame writes: 8 id digits, "##", a flags digit, 128 data digits, NUL.
inline constexpr std::size_t kMaxCanFrameTextLength = 8 + 2 + 1 + 2 * 64 + 1;

// Writes the frame's text and a terminating NUL into `out`; returns the characters written
// without the NUL, or 0 if `out` is too small. Real-time safe: no allocation; noexcept.
// Error frames are written as ERR:<8 hex digits of id>.
std::size_t FormatCanFrame(const CanFrame& frame, std::span<char> out) noexcept;

// Same, as a std::string (allocates: for logs and test messages).
std::string CanFrameToString(const CanFrame& frame);

// Parses the notation above. Nullopt for anything else: bad hex, an id beyond 11 bits in the
// 3-digit form or beyond 29 bits in the 8-digit form, more than 8 classic or 64 FD bytes, an FD
// length that is not a valid FD DLC length, an odd number of data digits. noexcept, no allocation.
std::optional<CanFrame> ParseCanFrame(std::string_view text) noexcept;

}  // namespace hrgbench::hw
