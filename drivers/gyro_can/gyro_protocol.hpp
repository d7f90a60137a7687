#pragma once
// The HRG electronics' CAN protocol, version 2: identifiers, lengths, enumerations and scalings.
// The human-readable specification is README.md in this folder and the machine-readable one is
// hrg_gyro_v2.dbc; tests/unit/gyro_can/dbc_consistency_test.cpp parses the DBC and checks it
// against these constants, so the three cannot drift apart.
//
// Conventions: standard 11-bit identifiers; every multi-byte field little-endian (Intel, DBC @1);
// the last payload byte of every frame is a CRC-8 (SAE J1850: poly 0x1D, init 0xFF, xor-out 0xFF,
// as AUTOSAR E2E profile 1) over the identifier (2 bytes, little-endian) and the preceding payload
// bytes. CAN's own CRC protects the wire; this one catches what it cannot: a gateway or driver
// that mangles a payload, a firmware writing a stale buffer, or injected corruption in tests.

#include <cstdint>

#include "hrgbench/hw/can_bus.hpp"
#include "hrgbench/hw/gyro_electronics.hpp"
#include "hrgbench/hw/gyro_link_load.hpp"

namespace hrgbench::drivers::gyro_can {

// Version 2 put the node id into every identifier (several units on one bus); version 1 had
// fixed identifiers and one unit per bus. A session records the version its log was spoken in.
inline constexpr std::uint8_t kProtocolVersion = 2;

// The electronics' node id on its bus: 0 … kMaxNodeId, set in the unit (hrg-gyro-sim --node).
// The low 4 bits of every identifier: id = message | node (CANopen's layout, function code in the
// high bits), so node ids never change which message wins arbitration.
using NodeId = std::uint8_t;
inline constexpr NodeId kMaxNodeId = 15;
inline constexpr std::uint32_t kNodeIdMask = 0x00F;

// Messages: node 0's identifier, the high 7 bits of every node's. Lower id wins arbitration:
// Stop before everything, then the other commands, their answers, and the sample stream last.
namespace can_id {
inline constexpr std::uint32_t kStop = 0x020;  // host → electronics
// host → electronics: one word of the compensation parameter block (README "Parameter block")
inline constexpr std::uint32_t kParameter = 0x030;
inline constexpr std::uint32_t kConfigure = 0x040;      // host → electronics
inline constexpr std::uint32_t kExcite = 0x050;         // host → electronics
inline constexpr std::uint32_t kRelease = 0x060;        // host → electronics
inline constexpr std::uint32_t kStatusRequest = 0x070;  // host → electronics
inline constexpr std::uint32_t kAck = 0x080;            // electronics → host, one per command
inline constexpr std::uint32_t kStatus = 0x090;    // electronics → host, periodic + requested
inline constexpr std::uint32_t kSampleA = 0x100;   // electronics → host: seq, y1, y2
inline constexpr std::uint32_t kSampleB = 0x110;   // electronics → host: seq, y3, y4
inline constexpr std::uint32_t kSampleFd = 0x120;  // electronics → host (CAN FD): 5 samples
// electronics → host: the demodulation reference's phase at every kReferencePhaseInterval-th
// sample (optional: electronics that do not report it never send it; README "Reference phase")
inline constexpr std::uint32_t kReferencePhase = 0x130;
// electronics → host, in the operating mode: the gyro's angle output and the wave's angle
inline constexpr std::uint32_t kOperatingSample = 0x140;
// electronics → host, in the operating mode, every kOperatingLoopsInterval-th sample after that
// sample's OperatingSample: the loops' state in two frames (README "Operating mode")
inline constexpr std::uint32_t kOperatingLoopsA = 0x150;  // seq, energy error, K̂/Ŝ
inline constexpr std::uint32_t kOperatingLoopsB = 0x160;  // seq, efforts g and q
}  // namespace can_id

// Node `node`'s identifier of `message` (a can_id constant), and the reverse.
constexpr std::uint32_t NodeMessageId(std::uint32_t message, NodeId node) noexcept {
  return message | (node & kNodeIdMask);
}
constexpr std::uint32_t MessageOf(std::uint32_t id) noexcept { return id & ~kNodeIdMask; }
constexpr NodeId NodeOf(std::uint32_t id) noexcept { return static_cast<NodeId>(id & kNodeIdMask); }
// Every frame of one node, both directions: what a unit's raw-frame tap records on a shared bus.
constexpr hw::CanFilter NodeTrafficFilter(NodeId node) noexcept {
  return hw::CanFilter{node & kNodeIdMask, kNodeIdMask, false};
}

// Payload lengths (DLC). Every frame has exactly this length; any other is a bad frame.
namespace length {
inline constexpr std::uint8_t kConfigure = 8;
inline constexpr std::uint8_t kExcite = 8;
inline constexpr std::uint8_t kSimpleCommand = 2;  // release, stop, status request
inline constexpr std::uint8_t kParameter = 8;
inline constexpr std::uint8_t kAck = 8;
inline constexpr std::uint8_t kStatus = 8;
inline constexpr std::uint8_t kSample = 8;
inline constexpr std::uint8_t kSampleFd = 64;
inline constexpr std::uint8_t kReferencePhase = 8;
inline constexpr std::uint8_t kOperatingSample = 8;
inline constexpr std::uint8_t kOperatingLoops = 8;  // both halves
}  // namespace length

// The command a frame carries (its message: CommandMessage), echoed in the Ack's byte 0. The codes
// are version 1's identifiers, kept so that an Ack reads the same in both versions.
enum class Command : std::uint8_t {
  kConfigure = 0x40,
  kExcite = 0x41,
  kRelease = 0x42,
  kStop = 0x43,
  kStatusRequest = 0x44,
  kParameter = 0x45,  // added in 2026-11 (version 2): not a version 1 identifier
};

constexpr std::uint32_t CommandMessage(Command command) noexcept {
  switch (command) {
    case Command::kConfigure:
      return can_id::kConfigure;
    case Command::kExcite:
      return can_id::kExcite;
    case Command::kRelease:
      return can_id::kRelease;
    case Command::kStop:
      return can_id::kStop;
    case Command::kStatusRequest:
      return can_id::kStatusRequest;
    case Command::kParameter:
      return can_id::kParameter;
  }
  return can_id::kStatusRequest;
}

enum class AckResult : std::uint8_t {
  kOk = 0,
  kBadState = 1,     // not allowed in the electronics' current mode
  kBadArgument = 2,  // a value out of range
  kFaulted = 3,      // a fault is latched: only Stop is accepted
};

// What a Parameter command does with the compensation parameter block (README "Parameter block").
// Every one is answered by an Ack whose arg is (word index << 16) | word value, except Commit's
// (the committed block's generation).
enum class ParameterOp : std::uint8_t {
  kBegin = 1,       // clear the staging block; value = the block's word count
  kWrite = 2,       // staging[index] = value
  kReadStaged = 3,  // answer staging[index]
  kReadActive = 4,  // answer the active block's word [index] from non-volatile memory
  kCommit = 5,      // check the staged block (layout, CRC-32) and write it to the other slot
  kRestore = 6,     // make the other slot active again, if it holds a valid block
};

// What Release starts (Configure byte 5).
enum class RunMode : std::uint8_t {
  kFreeRun = 0,     // control off, the wave decays: the y samples stream
  kWholeAngle = 1,  // the loops closed with the active parameter block: OperatingSample streams
};

// OperatingSample: the gyro's angle output ∫Ω̂ dt (rad) as int32 with LSB 2^-21 rad (±1024 rad),
// and the wave's electrical angle θ̂ modulo π as uint16 with LSB π/2^16 (the forms repeat every π).
inline constexpr double kAngleOutputLsbRad = 1.0 / 2097152.0;
inline constexpr double kWaveAngleLsbRad = 3.14159265358979323846 / 65536.0;

// OperatingLoopsA/B: what the whole-angle loops held at one sample (estimator::WholeAngleSample),
// for every sample whose number is a multiple of this (1 kHz: 100 reports/s, 200 frames/s, 2.2 …
// 2.7 % of a 1 Mbit/s bus). Often enough to watch the loops settle (their poles at −20 rad/s: 8
// reports per time constant at 1 kHz); rarely enough to cost a tenth of the angle output's load.
inline constexpr int kOperatingLoopsInterval = 10;
// Four int24 fields, saturating, each LSB chosen so that what a locked loop holds is resolved and
// what a noisy one holds (σ = 1e-4 on y: ≈ 1e-4 on K̂/Ŝ and Ŝ, ≈ 3e-3 on g and q per sample) fits:
// the energy error (Ŝ − S*)/S*: LSB 2^-28 (3.7e-9), ±1/32;
// the quadrature ratio K̂/Ŝ: LSB 2^-34 (5.8e-11: 1e-9 to 3 %), ±4.9e-4;
// the amplitude loop's effort g (1/s) and the quadrature loop's q (rad/s): LSB 2^-26 (1.5e-8: 1e-4
// to 1.5e-4), ±0.125 (an HRG's decay 1/τ and frequency split Δω are ≪ 0.1 1/s).
inline constexpr double kEnergyErrorLsb = 1.0 / 268435456.0;
inline constexpr double kQuadratureRatioLsb = 1.0 / 17179869184.0;
inline constexpr double kLoopEffortLsb = 1.0 / 67108864.0;
inline constexpr std::int32_t kLoopsRawMax = (1 << 23) - 1;
inline constexpr std::int32_t kLoopsRawMin = -(1 << 23);

enum class FrameFormat : std::uint8_t {
  kClassic = 0,  // two 8-byte frames per sample (SampleA, SampleB)
  kFd = 1,       // one 64-byte CAN FD frame per 5 samples (SampleFd)
};

// y on the wire: signed 24-bit, LSB = 2^-22 amplitude units, full scale ±2.0 (saturating).
inline constexpr double kSampleLsb = 1.0 / 4194304.0;
inline constexpr std::int32_t kSampleRawMax = (1 << 23) - 1;
inline constexpr std::int32_t kSampleRawMin = -(1 << 23);
// Excitation fields a (uint16), b and θ (int16): LSB 1e-4 (amplitude units, rad).
inline constexpr double kExciteLsb = 1e-4;
// Status: resonant frequency uint24 in mHz, temperature int16 in 0.01 °C.
inline constexpr double kFrequencyLsbHz = 1e-3;
inline constexpr double kTemperatureLsbC = 0.01;

inline constexpr int kSamplesPerFdFrame = 5;
// The reference phase χ (the demodulation reference's phase minus the ramp of the reference locked
// at release, as delayed by the output filter: aligned with the sample) is reported for every
// sample whose number is a multiple of this, before that sample's frames; the host interpolates
// between reports (χ moves by ≪ 1 rad per report). On the wire χ mod 2π as an unsigned 32-bit
// phase word, LSB 2π/2^32 rad (1.5e-9 rad).
inline constexpr int kReferencePhaseInterval = 5;
inline constexpr double kReferencePhaseLsbRad = 6.283185307179586476925286766559 / 4294967296.0;
// Highest sample rates the electronics accept: classic CAN at 1 Mbit/s carries two 8-byte frames
// per sample at ≤ 135 bits each (worst-case stuffing), so 2 kHz is 54 % bus load (README).
inline constexpr std::uint16_t kMaxClassicSampleRateHz = 2000;
inline constexpr std::uint16_t kMaxFdSampleRateHz = 10000;
static_assert(kMaxClassicSampleRateHz == hw::kMaxSampleRateClassicCanHz &&
                  kMaxFdSampleRateHz == hw::kMaxSampleRateCanFdHz,
              "the bench judges plans by hw/gyro_electronics.hpp's limits: keep them the same");
static_assert(((1 << 24) - 1) * kFrequencyLsbHz == hw::kMaxReportedResonantFrequencyHz);
inline constexpr std::uint8_t kDefaultStatusRateHz = 10;
static_assert(
    hw::kGyroClassicFramesPerSample == 2 && hw::kGyroClassicFrameBytes == length::kSample &&
        hw::kGyroClassicFrameBytes == length::kReferencePhase &&
        hw::kGyroClassicFrameBytes == length::kStatus &&
        hw::kGyroSamplesPerFdFrame == kSamplesPerFdFrame &&
        hw::kGyroFdFrameBytes == length::kSampleFd &&
        hw::kGyroSamplesPerReferencePhase == kReferencePhaseInterval &&
        hw::kGyroStatusRateHz == kDefaultStatusRateHz,
    "the bench plans bus load by hw/gyro_link_load.hpp's frame shapes: keep them the same");

// The electronics' sample counter on the wire: 8 bits on classic frames, 16 bits on FD frames.
inline constexpr std::uint32_t kClassicSeqModulo = 256;
inline constexpr std::uint32_t kFdSeqModulo = 65536;

}  // namespace hrgbench::drivers::gyro_can
