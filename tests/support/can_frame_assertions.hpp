#pragma once
// CAN frames in test assertions, printed in can-utils notation (STYLE rule 7) with the hardware
// layer's formatter (hrgbench/hw/can_frame_text.hpp), so a failing test prints frames one can paste
// into `cansend`: 123#DEADBEEF, 12345678#00, 123#R4, 123##1DEADBEEF, error frames as candump
// writes them (20000040#0000000000000000).

#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <ostream>

#include "hrgbench/hw/can_frame.hpp"
#include "hrgbench/hw/can_frame_text.hpp"

namespace hrgbench::hw {

// GoogleTest finds this by argument-dependent lookup when it prints a CanFrame.
inline void PrintTo(const CanFrame& frame, std::ostream* os) { *os << CanFrameToString(frame); }

}  // namespace hrgbench::hw

namespace hrgbench::testing {

// Same frame on the wire: identifier, kind, flags, length, and payload bytes within the length
// (a remote frame has none). Prints both frames in can-utils notation when they differ.
inline ::testing::AssertionResult SameFrame(const hw::CanFrame& expected,
                                            const hw::CanFrame& actual) {
  bool same = expected.id == actual.id && expected.extended == actual.extended &&
              expected.fd == actual.fd && expected.remote == actual.remote &&
              expected.error == actual.error && expected.length == actual.length &&
              (!expected.fd || expected.bit_rate_switch == actual.bit_rate_switch);
  for (std::uint8_t i = 0; same && !expected.remote && i < expected.length; ++i) {
    same = expected.data[i] == actual.data[i];
  }
  if (same) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "expected " << hw::CanFrameToString(expected) << ", got "
                                       << hw::CanFrameToString(actual);
}

// A frame from its can-utils text (a golden frame), failing the test when the text is not one.
inline hw::CanFrame FrameFromText(const char* text) {
  const std::optional<hw::CanFrame> frame = hw::ParseCanFrame(text);
  EXPECT_TRUE(frame.has_value()) << text;
  return frame.value_or(hw::CanFrame{});
}

}  // namespace hrgbench::testing
