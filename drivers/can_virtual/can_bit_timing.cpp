#include "can_virtual/can_bit_timing.hpp"

namespace hrgbench::drivers::can_virtual {
namespace {

// Fields after the CRC delimiter, common to classic and FD: ACK slot, ACK delimiter, end of
// frame (7), intermission (3).
constexpr std::int64_t kTrailerBits = 1 + 1 + 7 + 3;

std::int64_t CeilDiv(std::int64_t a, std::int64_t b) { return (a + b - 1) / b; }

}  // namespace

CanFrameBits CountFrameBits(const hw::CanFrame& frame) noexcept {
  const std::int64_t payload_bits = frame.remote ? 0 : 8 * std::int64_t{frame.length};
  if (!frame.fd) {
    // SOF, identifier (11, or 11 + SRR + IDE + 18), RTR, IDE/r1, r0, DLC, data, CRC 15, CRC delim.
    const std::int64_t header =
        frame.extended ? 1 + 11 + 1 + 1 + 18 + 1 + 2 + 4 : 1 + 11 + 1 + 1 + 1 + 4;
    return {header + payload_bits + 15 + 1 + kTrailerBits, 0};
  }
  // CAN FD: SOF, identifier, RRS, IDE, FDF, res, BRS at the nominal rate; then ESI, DLC, data,
  // stuff count (4), CRC (17 up to 16 bytes, else 21) and CRC delimiter at the data rate.
  const std::int64_t arbitration =
      frame.extended ? 1 + 11 + 1 + 1 + 18 + 1 + 1 + 1 + 1 : 1 + 11 + 1 + 1 + 1 + 1 + 1;
  const std::int64_t crc = frame.length <= 16 ? 17 : 21;
  const std::int64_t data_phase = 1 + 4 + payload_bits + 4 + crc + 1;
  if (frame.bit_rate_switch) return {arbitration + kTrailerBits, data_phase};
  return {arbitration + data_phase + kTrailerBits, 0};
}

std::int64_t FrameDurationNs(const hw::CanFrame& frame, std::int64_t nominal_bit_rate_bps,
                             std::int64_t data_bit_rate_bps) noexcept {
  constexpr std::int64_t kNsPerS = 1'000'000'000;
  const CanFrameBits bits = CountFrameBits(frame);
  const std::int64_t data_rate = data_bit_rate_bps > 0 ? data_bit_rate_bps : nominal_bit_rate_bps;
  return CeilDiv(bits.nominal_bits * kNsPerS, nominal_bit_rate_bps) +
         (bits.data_bits > 0 ? CeilDiv(bits.data_bits * kNsPerS, data_rate) : 0);
}

}  // namespace hrgbench::drivers::can_virtual
