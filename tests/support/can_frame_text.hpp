#pragma once
// CAN frames in can-utils notation (STYLE rule 7), so a failing test prints frames one can paste
// into `cansend`: 123#DEADBEEF (standard), 12345678#00 (extended: 8 hex digits), 123#R4 (remote,
// length 4), 123##1DEADBEEF (CAN FD, flags nibble: 1 = BRS). Error frames print as ERR:<class>.

#include <gtest/gtest.h>

#include <cstdio>
#include <ostream>
#include <string>

#include "hrgbench/hw/can_frame.hpp"

namespace hrgbench::hw {

inline std::string ToCanUtilsText(const CanFrame& frame) {
  char buffer[16];
  std::string text;
  if (frame.error) {
    std::snprintf(buffer, sizeof buffer, "ERR:%08X", frame.id);
    return buffer;
  }
  std::snprintf(buffer, sizeof buffer, frame.extended ? "%08X" : "%03X", frame.id);
  text = buffer;
  if (frame.remote) {
    std::snprintf(buffer, sizeof buffer, "#R%u", static_cast<unsigned>(frame.length));
    return text + buffer;
  }
  if (frame.fd) {
    std::snprintf(buffer, sizeof buffer, "##%X", frame.bit_rate_switch ? 1u : 0u);
    text += buffer;
  } else {
    text += '#';
  }
  for (std::uint8_t i = 0; i < frame.length && i < CanFrame::kMaxFdLength; ++i) {
    std::snprintf(buffer, sizeof buffer, "%02X", static_cast<unsigned>(frame.data[i]));
    text += buffer;
  }
  return text;
}

// GoogleTest finds this by argument-dependent lookup when it prints a CanFrame.
inline void PrintTo(const CanFrame& frame, std::ostream* os) { *os << ToCanUtilsText(frame); }

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
  return ::testing::AssertionFailure()
         << "expected " << hw::ToCanUtilsText(expected) << ", got " << hw::ToCanUtilsText(actual);
}

}  // namespace hrgbench::testing
