#pragma once
// The compensation parameter block the electronics hold in non-volatile memory (issue 28: the
// paper's p, written by the bench after an estimate). On the wire and in memory it is 48 16-bit
// words, moved one word per Parameter command (gyro_protocol.hpp, README "Parameter block"):
//
//   word 0        layout version (1)
//   word 1        value count (11)
//   words 2 … 45  the 11 values, each an IEEE 754 binary64, its 8 bytes little-endian as 4 words
//                 (low word first): δ1 … δ6, ξ1 … ξ4, b̂ (docs/estimator/operating-mode.md "What p
//                 holds"; SI units: 1/s, -, 1/s, 1/s, rad/s, rad/s, -, -, -, -, rad/s)
//   words 46, 47  CRC-32 (IEEE 802.3, as zlib's crc32) of words 0 … 45 as 92 little-endian bytes,
//                 low word first
//
// binary64 and not a scaled integer: δ2 must keep 1e-9 of 0.3 and ξ 1e-9 of 1e-2 (the estimate's
// std), which a 32-bit fixed point of one scale cannot hold for both.
// Pure, noexcept, no allocation.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "hrgbench/hw/operating_gyro.hpp"

namespace hrgbench::drivers::gyro_can {

inline constexpr std::uint16_t kParameterLayoutVersion = 1;
inline constexpr int kParameterValueCount = hw::kCompensationValueCount;
inline constexpr int kParameterBlockWords = 48;
// The block's values are hw's (hw/operating_gyro.hpp): the wire carries exactly what the interface
// hands over.
using ParameterValues = hw::CompensationValues;
static_assert(kParameterValueCount == 11, "the layout below holds 11 values");
using ParameterBlockWords = std::array<std::uint16_t, kParameterBlockWords>;

enum class ParameterBlockStatus : std::uint8_t {
  kOk,
  kBadLayout,  // word 0 is not a layout this host knows
  kBadCount,   // word 1 is not 11
  kBadCrc,     // words 46, 47 do not match the CRC-32 of words 0 … 45
  kNotFinite,  // a value is NaN or infinite
};
std::string_view ToString(ParameterBlockStatus status) noexcept;

// CRC-32 (IEEE 802.3: reflected polynomial 0xEDB88320, init and xor-out 0xFFFFFFFF; check value
// 0xCBF43926 for "123456789").
std::uint32_t Crc32(const std::uint8_t* data, std::size_t n) noexcept;

ParameterBlockWords EncodeParameterBlock(const ParameterValues& values) noexcept;
ParameterBlockStatus DecodeParameterBlock(const ParameterBlockWords& words,
                                          ParameterValues* out) noexcept;

}  // namespace hrgbench::drivers::gyro_can
