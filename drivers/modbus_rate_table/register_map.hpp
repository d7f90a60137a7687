#pragma once
// The rate table's Modbus register map (README.md in this folder is the human-readable version;
// keep the two in step) and the pure codec between registers and values. No libmodbus, no I/O:
// both the driver and the simulator (drivers/sim) use it, so they speak one wire format.
//
// 32-bit values are IEEE-754 float32 or uint32 in two registers, HIGH word first ("ABCD": register
// n holds bits 31..16, register n+1 bits 15..0; each register big-endian on the wire as Modbus
// requires).

#include <array>
#include <cstdint>
#include <span>

#include "hrgbench/hw/rate_table.hpp"

namespace hrgbench::drivers::modbus_rate_table {

// Version 2 adds the encoder angle (input registers 11..15) after version 1's status block, which
// is unchanged. The driver accepts both: with version 1 it has no angle (kNotSupported) and the
// bench measures Ω from the rate readings.
inline constexpr std::uint16_t kMapVersion = 2;
inline constexpr std::uint16_t kOldestMapVersion = 1;
inline constexpr std::uint16_t kFirstMapVersionWithAngle = 2;

// Holding registers: read with FC 03, written with FC 06 / FC 16 (FC 22 mask write and FC 23
// write-and-read are not implemented: exception 01). A refused write changes nothing. Per register,
// what a write is refused with (exception_code below; README.md has the table):
//   02 ILLEGAL DATA ADDRESS: any register outside 0..8; a write that covers only one half of a
//      float32 pair (2-3, 4-5), e.g. FC 06 to register 2, or FC 16 of registers 3-4 or 1-2.
//   03 ILLEGAL DATA VALUE: the value is out of the range given here.
//   04 SERVER DEVICE FAILURE: a motion command the table cannot carry out in its state: mode 1 or a
//      non-zero rate while a fault is latched or the e-stop is pressed (or mode 1 with the
//      interlock open, which also trips fault 3). Mode 0 and rate 0 are always accepted: a stop
//      must always be possible.
namespace holding {
inline constexpr int kMode = 0;         // RateTableMode, reads the mode actually active: 0 after a
                                        // fault. 03 unless 0 or 1; 04 for 1 while faulted/e-stop
inline constexpr int kReserved1 = 1;    // 0; keeps float32 pairs on even addresses. 03 unless 0
inline constexpr int kRateCommand = 2;  // float32 rad/s, registers 2-3, written as a pair (02).
                                        // 03 beyond the hardware limit; 04 if != 0 while faulted.
                                        // Keeps the last accepted setpoint after a fault.
inline constexpr int kAccelLimit = 4;   // float32 rad/s^2, registers 4-5, written as a pair (02).
                                        // 03 unless > 0 and <= the hardware maximum
inline constexpr int kHeartbeat = 6;    // uint16; every write refreshes the watchdog; any value
inline constexpr int kWatchdogMs = 7;   // uint16 ms, 100..60000, else 03
inline constexpr int kFaultReset = 8;   // write 1: clear latched faults, 0: no-op, else 03; reads 0
inline constexpr int kCount = 9;
// First registers of the float32 pairs: a write must cover both registers of a pair or neither.
inline constexpr std::array<int, 2> kFloatPairs = {kRateCommand, kAccelLimit};
}  // namespace holding

// Modbus exception codes the table answers with (the Modbus application protocol's numbering,
// which is libmodbus' MODBUS_EXCEPTION_*). Any exception is a definite answer: the driver never
// retries one.
namespace exception_code {
inline constexpr int kIllegalFunction = 1;      // function not implemented (FC 22, FC 23)
inline constexpr int kIllegalDataAddress = 2;   // unmapped register, or half of a float32 pair
inline constexpr int kIllegalDataValue = 3;     // value out of the register's range
inline constexpr int kServerDeviceFailure = 4;  // motion refused: fault, e-stop or interlock
}  // namespace exception_code

// Input registers (read-only, FC 04): the status block (0..10, one read of kStatusCount) and,
// from map version 2, the angle block (11..15, one read of kAngleCount from kAngleFirst).
namespace input {
inline constexpr int kStatusBits = 0;      // StatusBit flags
inline constexpr int kFaultCode = 1;       // RateTableFault
inline constexpr int kCommandedRate = 2;   // float32 rad/s, the setpoint being followed
inline constexpr int kMeasuredRate = 4;    // float32 rad/s
inline constexpr int kMode = 6;            // RateTableMode actually active
inline constexpr int kHeartbeatEcho = 7;   // last heartbeat value received
inline constexpr int kTemperature = 8;     // float32 °C
inline constexpr int kMapVersion = 10;     // kMapVersion
inline constexpr int kStatusCount = 11;    // the status block: registers 0..10 (all of version 1)
inline constexpr int kEncoderStatus = 11;  // EncoderBit flags
inline constexpr int kEncoderCount = 12;   // uint32, registers 12-13: count modulo 2^32
inline constexpr int kCountsPerRev = 14;   // uint32, registers 14-15: encoder resolution
inline constexpr int kAngleFirst = kEncoderStatus;
inline constexpr int kAngleCount = 5;  // the angle block: registers 11..15
inline constexpr int kCount = 16;      // every input register of version 2
}  // namespace input

// Bits of input::kEncoderStatus.
namespace encoder_bit {
inline constexpr std::uint16_t kPositionValid = 1u << 0;  // referenced, no encoder read error
}  // namespace encoder_bit

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

// uint32 <-> two registers, high word first (the encoder count and resolution).
std::array<std::uint16_t, 2> EncodeUint32(std::uint32_t value) noexcept;
std::uint32_t DecodeUint32(std::uint16_t high_word, std::uint16_t low_word) noexcept;

std::uint16_t PackStatusBits(const hw::RateTableStatus& status) noexcept;

// The status block (input 0..10) <-> a status (t_ns is not on the wire and is left 0). The block
// reports `map_version` in input register 10 (a simulator may serve an older map).
std::array<std::uint16_t, input::kStatusCount> EncodeStatusBlock(
    const hw::RateTableStatus& status, std::uint16_t map_version = kMapVersion) noexcept;
hw::RateTableStatus DecodeStatusBlock(
    std::span<const std::uint16_t, input::kStatusCount> regs) noexcept;

// The angle block (input 11..15) <-> an angle reading (t_ns and window_ns are not on the wire and
// are left 0; the reader stamps them).
std::array<std::uint16_t, input::kAngleCount> EncodeAngleBlock(
    const hw::RateTableAngle& angle) noexcept;
hw::RateTableAngle DecodeAngleBlock(
    std::span<const std::uint16_t, input::kAngleCount> regs) noexcept;

}  // namespace hrgbench::drivers::modbus_rate_table
