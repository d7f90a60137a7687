#pragma once
// The rate table's Modbus register map (README.md in this folder is the human-readable version;
// keep the two in step) and the pure codec between registers and values. No libmodbus, no I/O:
// both the driver and the simulator (drivers/sim) use it, so they speak one wire format.
//
// 32-bit values are IEEE-754 float32 in two registers, HIGH word first ("ABCD": register n holds
// bits 31..16, register n+1 bits 15..0; each register big-endian on the wire as Modbus requires).

#include <array>
#include <cstdint>
#include <span>

#include "hrgbench/hw/rate_table.hpp"

namespace hrgbench::modbus_table {

inline constexpr std::uint16_t kMapVersion = 1;

// Holding registers: read with FC 03, written with FC 06 / FC 16.
namespace holding {
inline constexpr int kMode = 0;         // RateTableMode
inline constexpr int kReserved1 = 1;    // 0; keeps float32 pairs on even addresses
inline constexpr int kRateCommand = 2;  // float32 rad/s, registers 2-3
inline constexpr int kAccelLimit = 4;   // float32 rad/s^2, registers 4-5
inline constexpr int kHeartbeat = 6;    // uint16; every write refreshes the watchdog
inline constexpr int kWatchdogMs = 7;   // uint16 ms, 100..60000
inline constexpr int kFaultReset = 8;   // write 1: clear latched faults; reads 0
inline constexpr int kCount = 9;
}  // namespace holding

// Input registers: read-only status block, read with one FC 04 of kCount registers.
namespace input {
inline constexpr int kStatusBits = 0;     // StatusBit flags
inline constexpr int kFaultCode = 1;      // RateTableFault
inline constexpr int kCommandedRate = 2;  // float32 rad/s, the setpoint being followed
inline constexpr int kMeasuredRate = 4;   // float32 rad/s
inline constexpr int kMode = 6;           // RateTableMode actually active
inline constexpr int kHeartbeatEcho = 7;  // last heartbeat value received
inline constexpr int kTemperature = 8;    // float32 °C
inline constexpr int kMapVersion = 10;    // kMapVersion
inline constexpr int kCount = 11;
}  // namespace input

// Bits of input::kStatusBits.
namespace status_bit {
inline constexpr std::uint16_t kRateStable = 1u << 0;
inline constexpr std::uint16_t kInMotion = 1u << 1;
inline constexpr std::uint16_t kFault = 1u << 2;
inline constexpr std::uint16_t kEStop = 1u << 3;
inline constexpr std::uint16_t kInterlockOpen = 1u << 4;
}  // namespace status_bit

inline constexpr std::uint16_t kMinWatchdogMs = 100;
inline constexpr std::uint16_t kMaxWatchdogMs = 60000;

// float32 <-> two registers, high word first.
std::array<std::uint16_t, 2> EncodeFloat32(float value) noexcept;
float DecodeFloat32(std::uint16_t high_word, std::uint16_t low_word) noexcept;
inline float DecodeFloat32(std::span<const std::uint16_t, 2> words) noexcept {
  return DecodeFloat32(words[0], words[1]);
}

std::uint16_t PackStatusBits(const hw::RateTableStatus& status) noexcept;

// The input register block <-> a status (t_ns is not on the wire and is left 0).
std::array<std::uint16_t, input::kCount> EncodeStatusBlock(
    const hw::RateTableStatus& status) noexcept;
hw::RateTableStatus DecodeStatusBlock(std::span<const std::uint16_t, input::kCount> regs) noexcept;

}  // namespace hrgbench::modbus_table
