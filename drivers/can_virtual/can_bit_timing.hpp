#pragma once
// How long a frame occupies a CAN bus: bit counts per ISO 11898-1 frame format, and the resulting
// time at a nominal (arbitration) and data (CAN FD with BRS) bit rate. Pure functions.
//
// Approximation, stated: no stuff bits are counted (the best case; a real frame is up to ~20%
// longer), the 3-bit intermission is included, and for CAN FD the fixed stuff bits of the CRC
// field are ignored. A classic 8-byte standard frame is 111 bits: 111 µs at 1 Mbit/s.

#include <cstdint>

#include "hrgbench/hw/can_frame.hpp"

namespace hrgbench::drivers::can_virtual {

struct CanFrameBits {
  std::int64_t nominal_bits = 0;  // sent at the nominal bit rate
  std::int64_t data_bits = 0;     // sent at the data bit rate (CAN FD with BRS only)
};

CanFrameBits CountFrameBits(const hw::CanFrame& frame) noexcept;

// Time on the bus in ns, rounded up. `data_bit_rate_bps` ≤ 0 means "same as nominal".
// Precondition: nominal_bit_rate_bps > 0.
std::int64_t FrameDurationNs(const hw::CanFrame& frame, std::int64_t nominal_bit_rate_bps,
                             std::int64_t data_bit_rate_bps) noexcept;

}  // namespace hrgbench::drivers::can_virtual
