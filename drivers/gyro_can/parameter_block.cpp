#include "gyro_can/parameter_block.hpp"

#include <bit>
#include <cmath>

namespace hrgbench::drivers::gyro_can {
namespace {

constexpr int kCrcWord = kParameterBlockWords - 2;

std::uint32_t BlockCrc(const ParameterBlockWords& words) noexcept {
  std::array<std::uint8_t, 2 * kCrcWord> bytes{};
  for (int i = 0; i < kCrcWord; ++i) {
    bytes[static_cast<std::size_t>(2 * i)] =
        static_cast<std::uint8_t>(words[static_cast<std::size_t>(i)]);
    bytes[static_cast<std::size_t>(2 * i + 1)] =
        static_cast<std::uint8_t>(words[static_cast<std::size_t>(i)] >> 8);
  }
  return Crc32(bytes.data(), bytes.size());
}

}  // namespace

std::string_view ToString(ParameterBlockStatus status) noexcept {
  switch (status) {
    case ParameterBlockStatus::kOk:
      return "ok";
    case ParameterBlockStatus::kBadLayout:
      return "unknown layout version";
    case ParameterBlockStatus::kBadCount:
      return "wrong value count";
    case ParameterBlockStatus::kBadCrc:
      return "CRC-32 mismatch";
    case ParameterBlockStatus::kNotFinite:
      return "a value is not finite";
  }
  return "?";
}

std::uint32_t Crc32(const std::uint8_t* data, std::size_t n) noexcept {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < n; ++i) {
    crc ^= data[i];
    for (int bit = 0; bit < 8; ++bit) crc = (crc & 1u) != 0 ? (crc >> 1) ^ 0xEDB88320u : crc >> 1;
  }
  return crc ^ 0xFFFFFFFFu;
}

ParameterBlockWords EncodeParameterBlock(const ParameterValues& values) noexcept {
  ParameterBlockWords words{};
  words[0] = kParameterLayoutVersion;
  words[1] = kParameterValueCount;
  for (int v = 0; v < kParameterValueCount; ++v) {
    const auto bits = std::bit_cast<std::uint64_t>(values[static_cast<std::size_t>(v)]);
    for (int w = 0; w < 4; ++w) {
      words[static_cast<std::size_t>(2 + 4 * v + w)] = static_cast<std::uint16_t>(bits >> (16 * w));
    }
  }
  const std::uint32_t crc = BlockCrc(words);
  words[kCrcWord] = static_cast<std::uint16_t>(crc);
  words[kCrcWord + 1] = static_cast<std::uint16_t>(crc >> 16);
  return words;
}

ParameterBlockStatus DecodeParameterBlock(const ParameterBlockWords& words,
                                          ParameterValues* out) noexcept {
  if (words[0] != kParameterLayoutVersion) return ParameterBlockStatus::kBadLayout;
  if (words[1] != kParameterValueCount) return ParameterBlockStatus::kBadCount;
  const std::uint32_t crc =
      words[kCrcWord] | (static_cast<std::uint32_t>(words[kCrcWord + 1]) << 16);
  if (crc != BlockCrc(words)) return ParameterBlockStatus::kBadCrc;
  ParameterValues values{};
  for (int v = 0; v < kParameterValueCount; ++v) {
    std::uint64_t bits = 0;
    for (int w = 0; w < 4; ++w) {
      bits |= static_cast<std::uint64_t>(words[static_cast<std::size_t>(2 + 4 * v + w)])
              << (16 * w);
    }
    values[static_cast<std::size_t>(v)] = std::bit_cast<double>(bits);
    if (!std::isfinite(values[static_cast<std::size_t>(v)]))
      return ParameterBlockStatus::kNotFinite;
  }
  if (out != nullptr) *out = values;
  return ParameterBlockStatus::kOk;
}

}  // namespace hrgbench::drivers::gyro_can
