#include <bit>

#include "modbus_rate_table/register_map.hpp"

namespace hrgbench::drivers::modbus_rate_table {

std::array<std::uint16_t, 2> EncodeFloat32(float value) noexcept {
  // bit_cast works on the value, not on memory, so this is independent of host byte order.
  const auto bits = std::bit_cast<std::uint32_t>(value);
  return {static_cast<std::uint16_t>(bits >> 16), static_cast<std::uint16_t>(bits & 0xFFFFu)};
}

float DecodeFloat32(std::uint16_t high_word, std::uint16_t low_word) noexcept {
  const std::uint32_t bits = (std::uint32_t{high_word} << 16) | std::uint32_t{low_word};
  return std::bit_cast<float>(bits);
}

std::array<std::uint16_t, 2> EncodeUint32(std::uint32_t value) noexcept {
  return {static_cast<std::uint16_t>(value >> 16), static_cast<std::uint16_t>(value & 0xFFFFu)};
}

std::uint32_t DecodeUint32(std::uint16_t high_word, std::uint16_t low_word) noexcept {
  return (std::uint32_t{high_word} << 16) | std::uint32_t{low_word};
}

std::uint16_t PackStatusBits(const hw::RateTableStatus& status) noexcept {
  std::uint16_t bits = 0;
  if (status.rate_stable) bits |= status_bit::kRateStable;
  if (status.in_motion) bits |= status_bit::kInMotion;
  if (status.fault) bits |= status_bit::kFault;
  if (status.estop) bits |= status_bit::kEStop;
  if (status.interlock_open) bits |= status_bit::kInterlockOpen;
  return bits;
}

std::array<std::uint16_t, input::kStatusCount> EncodeStatusBlock(
    const hw::RateTableStatus& status, std::uint16_t map_version) noexcept {
  std::array<std::uint16_t, input::kStatusCount> regs{};
  const auto put_float = [&regs](int address, double value) {
    const auto words = EncodeFloat32(static_cast<float>(value));
    regs[static_cast<std::size_t>(address)] = words[0];
    regs[static_cast<std::size_t>(address) + 1] = words[1];
  };
  regs[input::kStatusBits] = PackStatusBits(status);
  regs[input::kFaultCode] = status.fault_code;
  put_float(input::kCommandedRate, status.commanded_rate_rad_s);
  put_float(input::kMeasuredRate, status.measured_rate_rad_s);
  regs[input::kMode] = static_cast<std::uint16_t>(status.mode);
  regs[input::kHeartbeatEcho] = status.heartbeat_echo;
  put_float(input::kTemperature, status.temperature_c);
  regs[input::kMapVersion] = map_version;
  return regs;
}

hw::RateTableStatus DecodeStatusBlock(
    std::span<const std::uint16_t, input::kStatusCount> regs) noexcept {
  const auto get_float = [&regs](int address) {
    const auto i = static_cast<std::size_t>(address);
    return static_cast<double>(DecodeFloat32(regs[i], regs[i + 1]));
  };
  hw::RateTableStatus status;
  const std::uint16_t bits = regs[input::kStatusBits];
  status.rate_stable = (bits & status_bit::kRateStable) != 0;
  status.in_motion = (bits & status_bit::kInMotion) != 0;
  status.fault = (bits & status_bit::kFault) != 0;
  status.estop = (bits & status_bit::kEStop) != 0;
  status.interlock_open = (bits & status_bit::kInterlockOpen) != 0;
  status.fault_code = regs[input::kFaultCode];
  status.commanded_rate_rad_s = get_float(input::kCommandedRate);
  status.measured_rate_rad_s = get_float(input::kMeasuredRate);
  status.mode = static_cast<hw::RateTableMode>(regs[input::kMode]);
  status.heartbeat_echo = regs[input::kHeartbeatEcho];
  status.temperature_c = get_float(input::kTemperature);
  return status;
}

std::array<std::uint16_t, input::kAngleCount> EncodeAngleBlock(
    const hw::RateTableAngle& angle) noexcept {
  constexpr std::size_t kStatus = input::kEncoderStatus - input::kAngleFirst;
  constexpr std::size_t kCountAt = input::kEncoderCount - input::kAngleFirst;
  constexpr std::size_t kResolutionAt = input::kCountsPerRev - input::kAngleFirst;
  std::array<std::uint16_t, input::kAngleCount> regs{};
  regs[kStatus] = angle.valid ? encoder_bit::kPositionValid : 0;
  const auto count = EncodeUint32(angle.count);
  regs[kCountAt] = count[0];
  regs[kCountAt + 1] = count[1];
  const auto resolution = EncodeUint32(angle.counts_per_rev);
  regs[kResolutionAt] = resolution[0];
  regs[kResolutionAt + 1] = resolution[1];
  return regs;
}

hw::RateTableAngle DecodeAngleBlock(
    std::span<const std::uint16_t, input::kAngleCount> regs) noexcept {
  constexpr std::size_t kStatus = input::kEncoderStatus - input::kAngleFirst;
  constexpr std::size_t kCountAt = input::kEncoderCount - input::kAngleFirst;
  constexpr std::size_t kResolutionAt = input::kCountsPerRev - input::kAngleFirst;
  hw::RateTableAngle angle;
  angle.valid = (regs[kStatus] & encoder_bit::kPositionValid) != 0;
  angle.count = DecodeUint32(regs[kCountAt], regs[kCountAt + 1]);
  angle.counts_per_rev = DecodeUint32(regs[kResolutionAt], regs[kResolutionAt + 1]);
  return angle;
}

}  // namespace hrgbench::drivers::modbus_rate_table
