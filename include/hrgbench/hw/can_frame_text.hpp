#pragma once
// CAN frames in can-utils notation (cansend / candump, STYLE rule 7): the one formatter and parser
// of frames as text, for the bench's candump log, golden-frame tests and failure messages, so that
// a frame in a log or a message can be pasted into `cansend`:
//   123#DEADBEEF        standard id (3 hex digits), classic data
//   1ABCDEF0#00         extended id (8 hex digits)
//   123#R  123#R4       remote frame, optional length (written when 1..8)
//   123##1DEADBEEF      CAN FD: '##', one flags nibble (1 = BRS, 2 = ESI; ESI is ignored), data
//   20000040#0000000000000000
//                       error frame (written only): CAN_ERR_FLAG (0x20000000) | the class bits in
//                       `id`, 8 hex digits, then the data bytes (classic: at most 8)
// Formatting follows can-utils lib.c sprint_canframe() as candump -L writes it: upper-case hex, no
// separators; the id is masked to 11/29 bits, the length clamped to 8 (classic, error) or 64 (FD);
// an error frame is never FD or remote, and an FD frame is never remote (FD has no remote frames).
// Parsing accepts data with '.' between bytes (cansend accepts 11.22.33) and hex digits in either
// case. Depends on hw/can_frame.hpp and the standard library only.

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
// without the NUL, or 0 (nothing written) if `out` is too small. Any CanFrame has a text.
// Real-time safe: no allocation, no system call; noexcept; any thread.
std::size_t FormatCanFrame(const CanFrame& frame, std::span<char> out) noexcept;

// Same, as a std::string (allocates: for logs and test messages).
std::string CanFrameToString(const CanFrame& frame);

// Parses the notation above. Nullopt for anything else: bad hex, an id beyond 11 bits in the
// 3-digit form or beyond 29 bits in the 8-digit form (so error frames, whose text has
// CAN_ERR_FLAG set, are refused: the bench only writes them, to its log), more than 8 classic or
// 64 FD bytes, an FD length that is not a valid FD DLC length, an odd number of data digits.
// Every frame it returns formats back to a text that parses to the same frame.
// noexcept, no allocation; any thread.
std::optional<CanFrame> ParseCanFrame(std::string_view text) noexcept;

}  // namespace hrgbench::hw
