#pragma once
// GyroCodec: the pure codec of the HRG CAN protocol v2 (gyro_protocol.hpp, README.md,
// hrg_gyro_v2.dbc). Every frame is one node's: encoders take the node id, decoders accept only
// that node's identifier (another node's frame is kWrongId). No sockets, no clocks, no allocation;
// every function is noexcept and real-time safe. Encoders take values already validated by the
// caller and saturate anything out of the field's range (the command encoders' callers range-check
// first, so saturation never changes a command silently); decoders check identifier, frame kind,
// length, CRC and enumerated values, and report the first problem as a DecodeStatus.

#include <array>
#include <cstdint>
#include <string_view>

#include "gyro_can/gyro_protocol.hpp"
#include "hrgbench/hw/can_frame.hpp"

namespace hrgbench::drivers::gyro_can {

enum class DecodeStatus : std::uint8_t {
  kOk,
  kWrongId,      // not this message's identifier (or an extended id)
  kWrongKind,    // remote, error, FD where classic is specified, or the reverse
  kWrongLength,  // length differs from the specified DLC
  kBadChecksum,  // CRC-8 mismatch
  kBadValue,     // an enumerated field holds an undefined value, or a reserved field is set
};

constexpr std::string_view ToString(DecodeStatus status) noexcept {
  switch (status) {
    case DecodeStatus::kOk:
      return "ok";
    case DecodeStatus::kWrongId:
      return "wrong id";
    case DecodeStatus::kWrongKind:
      return "wrong frame kind";
    case DecodeStatus::kWrongLength:
      return "wrong length";
    case DecodeStatus::kBadChecksum:
      return "bad checksum";
    case DecodeStatus::kBadValue:
      return "bad value";
  }
  return "?";
}

struct ConfigureCommand {
  std::uint8_t token = 0;  // echoed in the Ack; a repeat with the same token is a retry
  std::uint16_t sample_rate_hz = 1000;
  FrameFormat format = FrameFormat::kClassic;
  std::uint8_t status_rate_hz = kDefaultStatusRateHz;  // 0: status only on request
  RunMode run_mode = RunMode::kFreeRun;
};

struct ExciteCommand {
  std::uint8_t token = 0;
  // Wire fields: a = a_raw·1e-4, b = b_raw·1e-4, θ = theta_raw·1e-4 rad.
  std::uint16_t a_raw = 10000;
  std::int16_t b_raw = 0;
  std::int16_t theta_raw = 0;
};

// Release, stop and status request carry only a token.
struct SimpleCommand {
  Command command = Command::kStatusRequest;
  std::uint8_t token = 0;
};

// One word of the compensation parameter block (parameter_block.hpp, README "Parameter block").
struct ParameterCommand {
  std::uint8_t token = 0;
  ParameterOp op = ParameterOp::kReadActive;
  std::uint8_t index = 0;   // word index 0 … kParameterBlockWords − 1 (Begin: 0)
  std::uint16_t value = 0;  // Write: the word; Begin: the block's word count; else 0
};

struct Ack {
  Command command = Command::kStatusRequest;  // which command this answers
  std::uint8_t token = 0;                     // the command's token
  AckResult result = AckResult::kOk;
  hw::GyroMode mode = hw::GyroMode::kIdle;  // the electronics' mode after the command
  // Command-specific, 24 bits: Configure: the accepted sample rate (Hz); Release: µs elapsed
  // between the release instant and this Ack's transmission (0 on the first Ack; larger on a
  // repeated Ack after a lost one) — the host subtracts it from the Ack's receive stamp;
  // Parameter: (word index << 16) | word value, Commit: the committed block's generation.
  std::uint32_t arg = 0;
};

struct StatusMessage {
  hw::GyroMode mode = hw::GyroMode::kIdle;
  bool pll_lock = false;
  bool ready = false;
  std::uint8_t fault_bits = 0;
  std::uint32_t frequency_mhz = 0;       // 24 bits: resonant frequency in mHz (≤ 16 777.215 Hz)
  std::int16_t temperature_centi_c = 0;  // 0.01 °C
};

// One half of a sample on classic CAN: half 0 (SampleA) carries y1, y2; half 1 (SampleB) y3, y4.
struct SampleHalf {
  std::uint8_t half = 0;
  std::uint8_t seq = 0;                 // sample number modulo 256
  std::array<std::int32_t, 2> y_raw{};  // int24 values
};

// Up to five consecutive samples in one CAN FD frame.
struct SampleFdBlock {
  std::uint16_t seq = 0;   // number of the first sample, modulo 65536
  std::uint8_t count = 0;  // 1 … kSamplesPerFdFrame; the unused sample slots are zero
  std::array<std::array<std::int32_t, 4>, kSamplesPerFdFrame> y_raw{};
};

// The reference phase at one sample (ReferencePhase): χ mod 2π = phase_raw·kReferencePhaseLsbRad.
struct ReferencePhaseReport {
  std::uint16_t seq = 0;        // number of the sample it belongs to, modulo 65536
  std::uint32_t phase_raw = 0;  // χ mod 2π in units of 2π/2^32 rad
};

// One sample of the operating mode (OperatingSample).
struct OperatingSampleFrame {
  std::uint8_t seq = 0;               // sample number modulo 256
  std::int32_t angle_output_raw = 0;  // ∫Ω̂ dt in kAngleOutputLsbRad (wraps at ±1024 rad)
  std::uint16_t wave_angle_raw = 0;   // θ̂ mod π in kWaveAngleLsbRad
};

// One half of the operating loops' report (OperatingLoopsA/B) of the sample numbered `seq`: half 0
// (A) carries the energy error and the quadrature ratio, half 1 (B) the efforts g and q; each
// value an int24 in its LSB (gyro_protocol.hpp), both halves the same seq.
struct OperatingLoopsHalf {
  std::uint8_t half = 0;
  std::uint8_t seq = 0;                     // sample number modulo 256 (OperatingSample's)
  std::array<std::int32_t, 2> value_raw{};  // A: energy error, K̂/Ŝ; B: g, q
};

// A loops value (its unit) ↔ int24 raw in `lsb`, rounding to nearest and saturating (NaN: 0).
std::int32_t QuantiseLoopValue(double value, double lsb) noexcept;

// χ (rad, any value) ↔ the phase word: χ mod 2π rounded to the nearest LSB (wraps at 2π).
std::uint32_t QuantiseReferencePhase(double chi_rad) noexcept;
constexpr double DequantiseReferencePhase(std::uint32_t raw) noexcept {
  return raw * kReferencePhaseLsbRad;
}

// CRC-8 SAE J1850 over the identifier (2 bytes LE) and bytes [0, n) of `data`.
std::uint8_t Crc8(std::uint32_t id, const std::uint8_t* data, std::size_t n) noexcept;

// y (amplitude units) ↔ int24 raw, rounding to nearest and saturating at ±full scale.
std::int32_t QuantiseY(double y) noexcept;
constexpr double DequantiseY(std::int32_t raw) noexcept { return raw * kSampleLsb; }

hw::CanFrame EncodeConfigure(NodeId node, const ConfigureCommand& command) noexcept;
hw::CanFrame EncodeExcite(NodeId node, const ExciteCommand& command) noexcept;
hw::CanFrame EncodeSimpleCommand(NodeId node, const SimpleCommand& command) noexcept;
hw::CanFrame EncodeParameter(NodeId node, const ParameterCommand& command) noexcept;
hw::CanFrame EncodeAck(NodeId node, const Ack& ack) noexcept;
hw::CanFrame EncodeStatus(NodeId node, const StatusMessage& status) noexcept;
hw::CanFrame EncodeSampleHalf(NodeId node, const SampleHalf& half) noexcept;
hw::CanFrame EncodeSampleFd(NodeId node, const SampleFdBlock& block) noexcept;  // FD with BRS
hw::CanFrame EncodeReferencePhase(NodeId node,
                                  const ReferencePhaseReport& report) noexcept;  // classic
hw::CanFrame EncodeOperatingSample(NodeId node, const OperatingSampleFrame& sample) noexcept;
hw::CanFrame EncodeOperatingLoopsHalf(NodeId node, const OperatingLoopsHalf& half) noexcept;

DecodeStatus DecodeConfigure(const hw::CanFrame& frame, NodeId node,
                             ConfigureCommand* out) noexcept;
DecodeStatus DecodeExcite(const hw::CanFrame& frame, NodeId node, ExciteCommand* out) noexcept;
DecodeStatus DecodeSimpleCommand(const hw::CanFrame& frame, NodeId node,
                                 SimpleCommand* out) noexcept;
DecodeStatus DecodeParameter(const hw::CanFrame& frame, NodeId node,
                             ParameterCommand* out) noexcept;
DecodeStatus DecodeAck(const hw::CanFrame& frame, NodeId node, Ack* out) noexcept;
DecodeStatus DecodeStatusMessage(const hw::CanFrame& frame, NodeId node,
                                 StatusMessage* out) noexcept;
DecodeStatus DecodeSampleHalf(const hw::CanFrame& frame, NodeId node, SampleHalf* out) noexcept;
DecodeStatus DecodeSampleFd(const hw::CanFrame& frame, NodeId node, SampleFdBlock* out) noexcept;
DecodeStatus DecodeReferencePhase(const hw::CanFrame& frame, NodeId node,
                                  ReferencePhaseReport* out) noexcept;
DecodeStatus DecodeOperatingSample(const hw::CanFrame& frame, NodeId node,
                                   OperatingSampleFrame* out) noexcept;
// Either half (the identifier says which).
DecodeStatus DecodeOperatingLoopsHalf(const hw::CanFrame& frame, NodeId node,
                                      OperatingLoopsHalf* out) noexcept;

// True for the identifiers this protocol defines in the given direction, of any node.
constexpr bool IsCommandId(std::uint32_t id) noexcept {
  const std::uint32_t message = MessageOf(id);
  return message == can_id::kStop || message == can_id::kParameter ||
         (message >= can_id::kConfigure && message <= can_id::kStatusRequest);
}
constexpr bool IsElectronicsId(std::uint32_t id) noexcept {
  const std::uint32_t message = MessageOf(id);
  return message == can_id::kAck || message == can_id::kStatus ||
         (message >= can_id::kSampleA && message <= can_id::kOperatingLoopsB);
}

}  // namespace hrgbench::drivers::gyro_can
