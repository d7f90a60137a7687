#pragma once
// A CAN or CAN FD frame as the hardware layer passes it around: no vendor header, plain data, fixed
// size (no allocation on the receive path).

#include <array>
#include <cstdint>

namespace hrgbench::hw {

struct CanFrame {
  static constexpr std::uint32_t kStandardIdMask = 0x7FFu;
  static constexpr std::uint32_t kExtendedIdMask = 0x1FFFFFFFu;
  static constexpr std::uint8_t kMaxClassicLength = 8;
  static constexpr std::uint8_t kMaxFdLength = 64;

  std::uint32_t id = 0;          // 11-bit or 29-bit identifier (without flag bits)
  bool extended = false;         // 29-bit identifier
  bool fd = false;               // CAN FD frame (length up to 64)
  bool bit_rate_switch = false;  // CAN FD BRS
  bool remote = false;           // classic RTR frame
  bool error = false;            // error frame (id holds the CAN_ERR_* class bits)
  std::uint8_t length = 0;       // payload bytes used, ≤ 8 classic, ≤ 64 FD (a valid FD length)
  std::array<std::uint8_t, kMaxFdLength> data{};
};

}  // namespace hrgbench::hw
