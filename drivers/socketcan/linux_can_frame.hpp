#pragma once
// Internal to the SocketCAN driver: conversion between hw::CanFrame and the kernel's canfd_frame
// (used for classic frames too: struct can_frame is its prefix), and constants taken from the
// kernel headers as typed values.

#include <linux/can.h>
#include <linux/can/raw.h>

#include <cstddef>
#include <cstdint>

#include "hrgbench/hw/can_frame.hpp"

namespace hrgbench::drivers::socketcan {

inline constexpr std::size_t kClassicMtu = CAN_MTU;  // bytes of a classic can_frame datagram
inline constexpr std::size_t kFdMtu = CANFD_MTU;     // bytes of a canfd_frame datagram

// Fills `out` (zeroing it first) and returns the datagram size to write: kClassicMtu or kFdMtu.
// Precondition: hw::IsValidCanFrame(frame, true).
std::size_t ToLinuxFrame(const hw::CanFrame& frame, canfd_frame* out) noexcept;

// Converts a received datagram of `bytes` (kClassicMtu or kFdMtu). Bytes beyond the length are
// zero in `out`. Returns false for any other size or an impossible length.
bool FromLinuxFrame(const canfd_frame& in, std::size_t bytes, hw::CanFrame* out) noexcept;

}  // namespace hrgbench::drivers::socketcan
