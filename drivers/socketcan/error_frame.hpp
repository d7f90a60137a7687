#pragma once
// Decoding of SocketCAN error frames (CAN_ERR_FLAG set; see <linux/can/error.h>) into the
// controller state of hw::CanBusState. A pure function, so it is tested without a kernel.
//
// Precedence, from the kernel's error classes: CAN_ERR_BUSOFF → bus-off; CAN_ERR_RESTARTED →
// error-active; CAN_ERR_CRTL data[1]: *_PASSIVE → passive, else *_WARNING → warning, else
// CAN_ERR_CRTL_ACTIVE → active. Failing those, CAN_ERR_CNT's counters (data[6] TX, data[7] RX)
// give the state by the ISO 11898-1 thresholds (≥ 128 passive, ≥ 96 warning, else active), except
// that counters never end bus-off (only a restart does). Anything else keeps `previous`.

#include <cstdint>
#include <span>

#include "hrgbench/hw/can_bus.hpp"

namespace hrgbench::drivers::socketcan {

struct ErrorFrameReport {
  hw::CanBusState state = hw::CanBusState::kUnknown;  // state after this error frame
  bool restarted = false;           // CAN_ERR_RESTARTED: the controller left bus-off
  bool rx_overflow = false;         // CAN_ERR_CRTL_RX_OVERFLOW: the controller lost frames
  bool tx_overflow = false;         // CAN_ERR_CRTL_TX_OVERFLOW
  bool has_error_counters = false;  // CAN_ERR_CNT: the counters below are valid
  std::uint8_t tx_error_counter = 0;
  std::uint8_t rx_error_counter = 0;
};

// `error_class`: the frame's can_id without CAN_ERR_FLAG (the CAN_ERR_* class bits);
// `data`: its 8 payload bytes. Real-time safe, noexcept.
ErrorFrameReport DecodeErrorFrame(std::uint32_t error_class, std::span<const std::uint8_t, 8> data,
                                  hw::CanBusState previous) noexcept;

}  // namespace hrgbench::drivers::socketcan
