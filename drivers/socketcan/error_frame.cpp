#include "socketcan/error_frame.hpp"

#include <linux/can/error.h>

namespace hrgbench::drivers::socketcan {

using hw::CanBusState;

ErrorFrameReport DecodeErrorFrame(std::uint32_t error_class, std::span<const std::uint8_t, 8> data,
                                  CanBusState previous) noexcept {
  ErrorFrameReport report;
  report.state = previous;
  const std::uint8_t controller = data[1];
  if ((error_class & CAN_ERR_CRTL) != 0) {
    report.rx_overflow = (controller & CAN_ERR_CRTL_RX_OVERFLOW) != 0;
    report.tx_overflow = (controller & CAN_ERR_CRTL_TX_OVERFLOW) != 0;
  }
  if ((error_class & CAN_ERR_CNT) != 0) {
    report.has_error_counters = true;
    report.tx_error_counter = data[6];
    report.rx_error_counter = data[7];
  }
  report.restarted = (error_class & CAN_ERR_RESTARTED) != 0;

  if ((error_class & CAN_ERR_BUSOFF) != 0) {
    report.state = CanBusState::kBusOff;
    return report;
  }
  if (report.restarted) {
    report.state = CanBusState::kErrorActive;
    return report;
  }
  if ((error_class & CAN_ERR_CRTL) != 0) {
    if ((controller & (CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE)) != 0) {
      report.state = CanBusState::kErrorPassive;
      return report;
    }
    if ((controller & (CAN_ERR_CRTL_RX_WARNING | CAN_ERR_CRTL_TX_WARNING)) != 0) {
      report.state = CanBusState::kErrorWarning;
      return report;
    }
    if ((controller & CAN_ERR_CRTL_ACTIVE) != 0) {
      report.state = CanBusState::kErrorActive;
      return report;
    }
  }
  if (report.has_error_counters && previous != CanBusState::kBusOff) {
    const unsigned worst = report.tx_error_counter > report.rx_error_counter
                               ? report.tx_error_counter
                               : report.rx_error_counter;
    report.state = worst >= CAN_ERROR_PASSIVE_THRESHOLD   ? CanBusState::kErrorPassive
                   : worst >= CAN_ERROR_WARNING_THRESHOLD ? CanBusState::kErrorWarning
                                                          : CanBusState::kErrorActive;
  }
  return report;
}

}  // namespace hrgbench::drivers::socketcan
