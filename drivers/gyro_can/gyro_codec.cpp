#include "gyro_can/gyro_codec.hpp"

#include <algorithm>
#include <cmath>

namespace hrgbench::drivers::gyro_can {
namespace {

using hw::CanFrame;

// Little-endian field access; `bytes` counts 1…4.
void PutUnsigned(CanFrame& frame, int offset, int bytes, std::uint32_t value) noexcept {
  for (int i = 0; i < bytes; ++i) {
    frame.data[static_cast<std::size_t>(offset + i)] = static_cast<std::uint8_t>(value >> (8 * i));
  }
}

std::uint32_t GetUnsigned(const CanFrame& frame, int offset, int bytes) noexcept {
  std::uint32_t value = 0;
  for (int i = 0; i < bytes; ++i) {
    value |= static_cast<std::uint32_t>(frame.data[static_cast<std::size_t>(offset + i)])
             << (8 * i);
  }
  return value;
}

// Sign-extends the low `bytes`·8 bits.
std::int32_t GetSigned(const CanFrame& frame, int offset, int bytes) noexcept {
  const std::uint32_t value = GetUnsigned(frame, offset, bytes);
  const int shift = 32 - 8 * bytes;
  return static_cast<std::int32_t>(value << shift) >> shift;
}

void PutSigned(CanFrame& frame, int offset, int bytes, std::int32_t value) noexcept {
  PutUnsigned(frame, offset, bytes, static_cast<std::uint32_t>(value));
}

CanFrame Begin(std::uint32_t id, std::uint8_t length) noexcept {
  CanFrame frame;
  frame.id = id;
  frame.length = length;
  return frame;
}

// Writes the CRC into the last payload byte.
CanFrame Seal(CanFrame frame) noexcept {
  const std::size_t last = frame.length - 1u;
  frame.data[last] = Crc8(frame.id, frame.data.data(), last);
  return frame;
}

DecodeStatus Check(const CanFrame& frame, std::uint32_t id, std::uint8_t length, bool fd) noexcept {
  if (frame.extended || frame.id != id) return DecodeStatus::kWrongId;
  if (frame.remote || frame.error || frame.fd != fd) return DecodeStatus::kWrongKind;
  if (frame.length != length) return DecodeStatus::kWrongLength;
  const std::size_t last = length - 1u;
  if (frame.data[last] != Crc8(frame.id, frame.data.data(), last))
    return DecodeStatus::kBadChecksum;
  return DecodeStatus::kOk;
}

bool IsCommand(std::uint8_t value) noexcept {
  return value >= static_cast<std::uint8_t>(Command::kConfigure) &&
         value <= static_cast<std::uint8_t>(Command::kParameter);
}
bool IsMode(std::uint32_t value) noexcept {
  return value <= static_cast<std::uint8_t>(hw::GyroMode::kOperating);
}

}  // namespace

std::uint8_t Crc8(std::uint32_t id, const std::uint8_t* data, std::size_t n) noexcept {
  // Bitwise: at most 65 bytes per frame, so a 256-byte table buys nothing measurable here.
  std::uint8_t crc = 0xFF;
  const auto feed = [&crc](std::uint8_t byte) {
    crc ^= byte;
    for (int bit = 0; bit < 8; ++bit) {
      crc = static_cast<std::uint8_t>((crc & 0x80u) != 0 ? (crc << 1) ^ 0x1Du : crc << 1);
    }
  };
  feed(static_cast<std::uint8_t>(id));
  feed(static_cast<std::uint8_t>(id >> 8));
  for (std::size_t i = 0; i < n; ++i) feed(data[i]);
  return static_cast<std::uint8_t>(crc ^ 0xFFu);
}

std::int32_t QuantiseY(double y) noexcept {
  if (std::isnan(y)) return 0;
  const double raw = std::nearbyint(y / kSampleLsb);
  if (raw >= kSampleRawMax) return kSampleRawMax;
  if (raw <= kSampleRawMin) return kSampleRawMin;
  return static_cast<std::int32_t>(raw);
}

CanFrame EncodeConfigure(NodeId node, const ConfigureCommand& command) noexcept {
  CanFrame frame = Begin(NodeMessageId(can_id::kConfigure, node), length::kConfigure);
  frame.data[0] = command.token;
  PutUnsigned(frame, 1, 2, command.sample_rate_hz);
  frame.data[3] = static_cast<std::uint8_t>(command.format);
  frame.data[4] = command.status_rate_hz;
  frame.data[5] = static_cast<std::uint8_t>(command.run_mode);
  return Seal(frame);
}

CanFrame EncodeExcite(NodeId node, const ExciteCommand& command) noexcept {
  CanFrame frame = Begin(NodeMessageId(can_id::kExcite, node), length::kExcite);
  frame.data[0] = command.token;
  PutUnsigned(frame, 1, 2, command.a_raw);
  PutSigned(frame, 3, 2, command.b_raw);
  PutSigned(frame, 5, 2, command.theta_raw);
  return Seal(frame);
}

CanFrame EncodeSimpleCommand(NodeId node, const SimpleCommand& command) noexcept {
  CanFrame frame =
      Begin(NodeMessageId(CommandMessage(command.command), node), length::kSimpleCommand);
  frame.data[0] = command.token;
  return Seal(frame);
}

CanFrame EncodeParameter(NodeId node, const ParameterCommand& command) noexcept {
  CanFrame frame = Begin(NodeMessageId(can_id::kParameter, node), length::kParameter);
  frame.data[0] = command.token;
  frame.data[1] = static_cast<std::uint8_t>(command.op);
  frame.data[2] = command.index;
  PutUnsigned(frame, 3, 2, command.value);
  return Seal(frame);
}

CanFrame EncodeOperatingSample(NodeId node, const OperatingSampleFrame& sample) noexcept {
  CanFrame frame = Begin(NodeMessageId(can_id::kOperatingSample, node), length::kOperatingSample);
  frame.data[0] = sample.seq;
  PutUnsigned(frame, 1, 4, static_cast<std::uint32_t>(sample.angle_output_raw));
  PutUnsigned(frame, 5, 2, sample.wave_angle_raw);
  return Seal(frame);
}

std::int32_t QuantiseLoopValue(double value, double lsb) noexcept {
  if (std::isnan(value)) return 0;
  const double raw = std::nearbyint(value / lsb);
  if (raw >= kLoopsRawMax) return kLoopsRawMax;
  if (raw <= kLoopsRawMin) return kLoopsRawMin;
  return static_cast<std::int32_t>(raw);
}

CanFrame EncodeOperatingLoopsHalf(NodeId node, const OperatingLoopsHalf& half) noexcept {
  CanFrame frame = Begin(
      NodeMessageId(half.half == 0 ? can_id::kOperatingLoopsA : can_id::kOperatingLoopsB, node),
      length::kOperatingLoops);
  frame.data[0] = half.seq;
  PutSigned(frame, 1, 3, std::clamp(half.value_raw[0], kLoopsRawMin, kLoopsRawMax));
  PutSigned(frame, 4, 3, std::clamp(half.value_raw[1], kLoopsRawMin, kLoopsRawMax));
  return Seal(frame);
}

CanFrame EncodeAck(NodeId node, const Ack& ack) noexcept {
  CanFrame frame = Begin(NodeMessageId(can_id::kAck, node), length::kAck);
  frame.data[0] = static_cast<std::uint8_t>(ack.command);
  frame.data[1] = ack.token;
  frame.data[2] = static_cast<std::uint8_t>(ack.result);
  frame.data[3] = static_cast<std::uint8_t>(ack.mode);
  PutUnsigned(frame, 4, 3, ack.arg > 0xFFFFFFu ? 0xFFFFFFu : ack.arg);
  return Seal(frame);
}

CanFrame EncodeStatus(NodeId node, const StatusMessage& status) noexcept {
  CanFrame frame = Begin(NodeMessageId(can_id::kStatus, node), length::kStatus);
  frame.data[0] = static_cast<std::uint8_t>(static_cast<std::uint8_t>(status.mode) & 0x0Fu) |
                  static_cast<std::uint8_t>(status.pll_lock ? 0x10u : 0u) |
                  static_cast<std::uint8_t>(status.ready ? 0x20u : 0u);
  frame.data[1] = status.fault_bits;
  PutUnsigned(frame, 2, 3, status.frequency_mhz > 0xFFFFFFu ? 0xFFFFFFu : status.frequency_mhz);
  PutSigned(frame, 5, 2, status.temperature_centi_c);
  return Seal(frame);
}

CanFrame EncodeSampleHalf(NodeId node, const SampleHalf& half) noexcept {
  CanFrame frame = Begin(NodeMessageId(half.half == 0 ? can_id::kSampleA : can_id::kSampleB, node),
                         length::kSample);
  frame.data[0] = half.seq;
  PutSigned(frame, 1, 3, half.y_raw[0]);
  PutSigned(frame, 4, 3, half.y_raw[1]);
  return Seal(frame);
}

CanFrame EncodeSampleFd(NodeId node, const SampleFdBlock& block) noexcept {
  CanFrame frame = Begin(NodeMessageId(can_id::kSampleFd, node), length::kSampleFd);
  frame.fd = true;
  frame.bit_rate_switch = true;
  PutUnsigned(frame, 0, 2, block.seq);
  const int count = block.count > kSamplesPerFdFrame ? kSamplesPerFdFrame : block.count;
  frame.data[2] = static_cast<std::uint8_t>(count);
  for (int s = 0; s < count; ++s) {
    for (int c = 0; c < 4; ++c) {
      PutSigned(frame, 3 + 12 * s + 3 * c, 3,
                block.y_raw[static_cast<std::size_t>(s)][static_cast<std::size_t>(c)]);
    }
  }
  return Seal(frame);
}

DecodeStatus DecodeConfigure(const CanFrame& frame, NodeId node, ConfigureCommand* out) noexcept {
  const DecodeStatus status =
      Check(frame, NodeMessageId(can_id::kConfigure, node), length::kConfigure, false);
  if (status != DecodeStatus::kOk) return status;
  if (frame.data[3] > static_cast<std::uint8_t>(FrameFormat::kFd) ||
      frame.data[5] > static_cast<std::uint8_t>(RunMode::kWholeAngle) || frame.data[6] != 0) {
    return DecodeStatus::kBadValue;
  }
  out->token = frame.data[0];
  out->sample_rate_hz = static_cast<std::uint16_t>(GetUnsigned(frame, 1, 2));
  out->format = static_cast<FrameFormat>(frame.data[3]);
  out->status_rate_hz = frame.data[4];
  out->run_mode = static_cast<RunMode>(frame.data[5]);
  return DecodeStatus::kOk;
}

DecodeStatus DecodeExcite(const CanFrame& frame, NodeId node, ExciteCommand* out) noexcept {
  const DecodeStatus status =
      Check(frame, NodeMessageId(can_id::kExcite, node), length::kExcite, false);
  if (status != DecodeStatus::kOk) return status;
  out->token = frame.data[0];
  out->a_raw = static_cast<std::uint16_t>(GetUnsigned(frame, 1, 2));
  out->b_raw = static_cast<std::int16_t>(GetSigned(frame, 3, 2));
  out->theta_raw = static_cast<std::int16_t>(GetSigned(frame, 5, 2));
  return DecodeStatus::kOk;
}

DecodeStatus DecodeSimpleCommand(const CanFrame& frame, NodeId node, SimpleCommand* out) noexcept {
  const std::uint32_t message = MessageOf(frame.id);
  Command command = Command::kStatusRequest;
  if (message == can_id::kRelease) {
    command = Command::kRelease;
  } else if (message == can_id::kStop) {
    command = Command::kStop;
  } else if (message != can_id::kStatusRequest) {
    return DecodeStatus::kWrongId;
  }
  const DecodeStatus status =
      Check(frame, NodeMessageId(message, node), length::kSimpleCommand, false);
  if (status != DecodeStatus::kOk) return status;
  out->command = command;
  out->token = frame.data[0];
  return DecodeStatus::kOk;
}

DecodeStatus DecodeParameter(const CanFrame& frame, NodeId node, ParameterCommand* out) noexcept {
  const DecodeStatus status =
      Check(frame, NodeMessageId(can_id::kParameter, node), length::kParameter, false);
  if (status != DecodeStatus::kOk) return status;
  if (frame.data[1] < static_cast<std::uint8_t>(ParameterOp::kBegin) ||
      frame.data[1] > static_cast<std::uint8_t>(ParameterOp::kRestore) || frame.data[5] != 0 ||
      frame.data[6] != 0) {
    return DecodeStatus::kBadValue;
  }
  out->token = frame.data[0];
  out->op = static_cast<ParameterOp>(frame.data[1]);
  out->index = frame.data[2];
  out->value = static_cast<std::uint16_t>(GetUnsigned(frame, 3, 2));
  return DecodeStatus::kOk;
}

DecodeStatus DecodeOperatingSample(const CanFrame& frame, NodeId node,
                                   OperatingSampleFrame* out) noexcept {
  const DecodeStatus status =
      Check(frame, NodeMessageId(can_id::kOperatingSample, node), length::kOperatingSample, false);
  if (status != DecodeStatus::kOk) return status;
  out->seq = frame.data[0];
  out->angle_output_raw = static_cast<std::int32_t>(GetUnsigned(frame, 1, 4));
  out->wave_angle_raw = static_cast<std::uint16_t>(GetUnsigned(frame, 5, 2));
  return DecodeStatus::kOk;
}

DecodeStatus DecodeOperatingLoopsHalf(const CanFrame& frame, NodeId node,
                                      OperatingLoopsHalf* out) noexcept {
  const std::uint32_t message = MessageOf(frame.id);
  if (message != can_id::kOperatingLoopsA && message != can_id::kOperatingLoopsB) {
    return DecodeStatus::kWrongId;
  }
  const DecodeStatus status =
      Check(frame, NodeMessageId(message, node), length::kOperatingLoops, false);
  if (status != DecodeStatus::kOk) return status;
  out->half = message == can_id::kOperatingLoopsA ? 0 : 1;
  out->seq = frame.data[0];
  out->value_raw[0] = GetSigned(frame, 1, 3);
  out->value_raw[1] = GetSigned(frame, 4, 3);
  return DecodeStatus::kOk;
}

DecodeStatus DecodeAck(const CanFrame& frame, NodeId node, Ack* out) noexcept {
  const DecodeStatus status = Check(frame, NodeMessageId(can_id::kAck, node), length::kAck, false);
  if (status != DecodeStatus::kOk) return status;
  if (!IsCommand(frame.data[0]) || frame.data[2] > static_cast<std::uint8_t>(AckResult::kFaulted) ||
      !IsMode(frame.data[3])) {
    return DecodeStatus::kBadValue;
  }
  out->command = static_cast<Command>(frame.data[0]);
  out->token = frame.data[1];
  out->result = static_cast<AckResult>(frame.data[2]);
  out->mode = static_cast<hw::GyroMode>(frame.data[3]);
  out->arg = GetUnsigned(frame, 4, 3);
  return DecodeStatus::kOk;
}

DecodeStatus DecodeStatusMessage(const CanFrame& frame, NodeId node, StatusMessage* out) noexcept {
  const DecodeStatus status =
      Check(frame, NodeMessageId(can_id::kStatus, node), length::kStatus, false);
  if (status != DecodeStatus::kOk) return status;
  const std::uint8_t mode = frame.data[0] & 0x0Fu;
  if (!IsMode(mode) || (frame.data[0] & 0xC0u) != 0) return DecodeStatus::kBadValue;
  out->mode = static_cast<hw::GyroMode>(mode);
  out->pll_lock = (frame.data[0] & 0x10u) != 0;
  out->ready = (frame.data[0] & 0x20u) != 0;
  out->fault_bits = frame.data[1];
  out->frequency_mhz = GetUnsigned(frame, 2, 3);
  out->temperature_centi_c = static_cast<std::int16_t>(GetSigned(frame, 5, 2));
  return DecodeStatus::kOk;
}

std::uint32_t QuantiseReferencePhase(double chi_rad) noexcept {
  if (!std::isfinite(chi_rad)) return 0;
  constexpr double kTwoPi = 4294967296.0 * kReferencePhaseLsbRad;
  double turns = std::fmod(chi_rad, kTwoPi);
  if (turns < 0.0) turns += kTwoPi;
  const double raw = std::round(turns / kReferencePhaseLsbRad);
  return raw >= 4294967296.0 ? 0u : static_cast<std::uint32_t>(raw);  // 2π rounds to 0
}

CanFrame EncodeReferencePhase(NodeId node, const ReferencePhaseReport& report) noexcept {
  CanFrame frame = Begin(NodeMessageId(can_id::kReferencePhase, node), length::kReferencePhase);
  PutUnsigned(frame, 0, 2, report.seq);
  PutUnsigned(frame, 2, 4, report.phase_raw);
  return Seal(frame);
}

DecodeStatus DecodeReferencePhase(const CanFrame& frame, NodeId node,
                                  ReferencePhaseReport* out) noexcept {
  const DecodeStatus status =
      Check(frame, NodeMessageId(can_id::kReferencePhase, node), length::kReferencePhase, false);
  if (status != DecodeStatus::kOk) return status;
  if (frame.data[6] != 0) return DecodeStatus::kBadValue;  // reserved
  out->seq = static_cast<std::uint16_t>(GetUnsigned(frame, 0, 2));
  out->phase_raw = GetUnsigned(frame, 2, 4);
  return DecodeStatus::kOk;
}

DecodeStatus DecodeSampleHalf(const CanFrame& frame, NodeId node, SampleHalf* out) noexcept {
  const std::uint32_t message = MessageOf(frame.id);
  if (message != can_id::kSampleA && message != can_id::kSampleB) return DecodeStatus::kWrongId;
  const DecodeStatus status = Check(frame, NodeMessageId(message, node), length::kSample, false);
  if (status != DecodeStatus::kOk) return status;
  out->half = message == can_id::kSampleA ? 0 : 1;
  out->seq = frame.data[0];
  out->y_raw[0] = GetSigned(frame, 1, 3);
  out->y_raw[1] = GetSigned(frame, 4, 3);
  return DecodeStatus::kOk;
}

DecodeStatus DecodeSampleFd(const CanFrame& frame, NodeId node, SampleFdBlock* out) noexcept {
  const DecodeStatus status =
      Check(frame, NodeMessageId(can_id::kSampleFd, node), length::kSampleFd, true);
  if (status != DecodeStatus::kOk) return status;
  const std::uint8_t count = frame.data[2];
  if (count == 0 || count > kSamplesPerFdFrame) return DecodeStatus::kBadValue;
  out->seq = static_cast<std::uint16_t>(GetUnsigned(frame, 0, 2));
  out->count = count;
  for (std::size_t s = 0; s < kSamplesPerFdFrame; ++s) {
    for (std::size_t c = 0; c < 4; ++c) {
      out->y_raw[s][c] = s < count ? GetSigned(frame, static_cast<int>(3 + 12 * s + 3 * c), 3) : 0;
    }
  }
  return DecodeStatus::kOk;
}

}  // namespace hrgbench::drivers::gyro_can
