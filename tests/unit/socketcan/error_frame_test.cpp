// Error frames as the kernel's CAN drivers send them (can_id class bits + 8 data bytes), decoded
// into the controller state.

#include "socketcan/error_frame.hpp"

#include <gtest/gtest.h>
#include <linux/can/error.h>

#include <array>

namespace hrgbench::drivers::socketcan {
namespace {

using hw::CanBusState;
using Payload = std::array<std::uint8_t, 8>;

ErrorFrameReport Decode(std::uint32_t error_class, Payload data,
                        CanBusState previous = CanBusState::kErrorActive) {
  return DecodeErrorFrame(error_class, data, previous);
}

Payload Controller(std::uint8_t bits) { return {0, bits, 0, 0, 0, 0, 0, 0}; }

TEST(DecodeErrorFrame, ControllerWarningAndPassiveLevels) {
  EXPECT_EQ(Decode(CAN_ERR_CRTL, Controller(CAN_ERR_CRTL_RX_WARNING)).state,
            CanBusState::kErrorWarning);
  EXPECT_EQ(Decode(CAN_ERR_CRTL, Controller(CAN_ERR_CRTL_TX_WARNING)).state,
            CanBusState::kErrorWarning);
  EXPECT_EQ(Decode(CAN_ERR_CRTL, Controller(CAN_ERR_CRTL_TX_PASSIVE)).state,
            CanBusState::kErrorPassive);
  // Passive wins over warning when a driver reports both directions at once.
  EXPECT_EQ(
      Decode(CAN_ERR_CRTL, Controller(CAN_ERR_CRTL_RX_WARNING | CAN_ERR_CRTL_TX_PASSIVE)).state,
      CanBusState::kErrorPassive);
  EXPECT_EQ(Decode(CAN_ERR_CRTL, Controller(CAN_ERR_CRTL_ACTIVE), CanBusState::kErrorPassive).state,
            CanBusState::kErrorActive);
}

TEST(DecodeErrorFrame, BusOffAndRestart) {
  EXPECT_EQ(Decode(CAN_ERR_BUSOFF, Payload{}).state, CanBusState::kBusOff);
  // Linux sends bus-off with the controller's passive bits often set too: bus-off wins.
  EXPECT_EQ(Decode(CAN_ERR_BUSOFF | CAN_ERR_CRTL, Controller(CAN_ERR_CRTL_TX_PASSIVE)).state,
            CanBusState::kBusOff);
  const ErrorFrameReport restarted = Decode(CAN_ERR_RESTARTED, Payload{}, CanBusState::kBusOff);
  EXPECT_EQ(restarted.state, CanBusState::kErrorActive);
  EXPECT_TRUE(restarted.restarted);
}

TEST(DecodeErrorFrame, OverflowBitsAloneKeepTheState) {
  const ErrorFrameReport report =
      Decode(CAN_ERR_CRTL, Controller(CAN_ERR_CRTL_RX_OVERFLOW), CanBusState::kErrorWarning);
  EXPECT_EQ(report.state, CanBusState::kErrorWarning);
  EXPECT_TRUE(report.rx_overflow);
  EXPECT_FALSE(report.tx_overflow);
}

TEST(DecodeErrorFrame, ErrorCountersGiveTheStateWhenTheControllerSaysNothing) {
  // A protocol error with counters (CAN_ERR_CNT: data[6] TX, data[7] RX), as recent kernels send.
  const std::uint32_t bus_error = CAN_ERR_PROT | CAN_ERR_BUSERROR | CAN_ERR_CNT;
  ErrorFrameReport report = Decode(bus_error, Payload{0, 0, CAN_ERR_PROT_BIT, 0, 0, 0, 8, 0});
  EXPECT_TRUE(report.has_error_counters);
  EXPECT_EQ(report.tx_error_counter, 8);
  EXPECT_EQ(report.state, CanBusState::kErrorActive);
  EXPECT_EQ(Decode(bus_error, Payload{0, 0, 0, 0, 0, 0, 0, 96}).state, CanBusState::kErrorWarning);
  EXPECT_EQ(Decode(bus_error, Payload{0, 0, 0, 0, 0, 0, 128, 5}).state, CanBusState::kErrorPassive);
  // Counters never end bus-off; only a restart does.
  EXPECT_EQ(Decode(bus_error, Payload{}, CanBusState::kBusOff).state, CanBusState::kBusOff);
}

TEST(DecodeErrorFrame, UnrelatedClassesKeepThePreviousState) {
  EXPECT_EQ(Decode(CAN_ERR_ACK, Payload{}, CanBusState::kUnknown).state, CanBusState::kUnknown);
  EXPECT_EQ(Decode(CAN_ERR_LOSTARB, Payload{}, CanBusState::kErrorPassive).state,
            CanBusState::kErrorPassive);
}

}  // namespace
}  // namespace hrgbench::drivers::socketcan
