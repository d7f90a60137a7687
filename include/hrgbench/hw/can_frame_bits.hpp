#pragma once
// How long a frame occupies a CAN bus: bit counts per ISO 11898-1 frame format, and the resulting
// time at a nominal (arbitration) and data (CAN FD with BRS) bit rate. Pure constexpr functions,
// used by the in-process virtual bus (its timeline) and by the bench's bus planning (a plan's
// load).
//
// Two counts:
//   - CountFrameBits: no stuff bits (the best case; what the virtual bus times frames by). The
//     3-bit intermission is included; for CAN FD the fixed stuff bits of the CRC field are not. A
//     classic 8-byte standard frame is 111 bits: 111 µs at 1 Mbit/s.
//   - WorstCaseFrameBits: the most stuff bits the frame can need, for planning. Dynamic stuffing
//     inserts at most one bit per four after the first over SOF … CRC (classic) or SOF … data (FD,
//     each phase at its own rate); CAN FD adds a fixed stuff bit before the stuff count and one
//     per four bits of the CRC. A classic 8-byte standard frame is 111 + ⌊97/4⌋ = 135 bits.
//   - StuffedFrameBits: the bits the frame really takes: a classic frame with the stuff bits its
//     own bit stream needs (identifier, DLC, data and CRC-15 as sent; a bus of several units
//     timed by it runs as full as a real one); a CAN FD frame at its worst case.

#include <cstdint>

#include "hrgbench/hw/can_frame.hpp"

namespace hrgbench::hw {

struct CanFrameBits {
  std::int64_t nominal_bits = 0;  // sent at the nominal bit rate
  std::int64_t data_bits = 0;     // sent at the data bit rate (CAN FD with BRS only)
};

namespace can_frame_bits_detail {
// Fields after the CRC delimiter, common to classic and FD: ACK slot, ACK delimiter, end of
// frame (7), intermission (3).
inline constexpr std::int64_t kTrailerBits = 1 + 1 + 7 + 3;
constexpr std::int64_t CeilDiv(std::int64_t a, std::int64_t b) { return (a + b - 1) / b; }
// Dynamic stuff bits at most: after the first bit, one per four equal bits.
constexpr std::int64_t MaxStuffBits(std::int64_t stuffed_bits) {
  return stuffed_bits > 0 ? (stuffed_bits - 1) / 4 : 0;
}
// SOF, identifier, and the bits up to (classic) the DLC or (FD) the BRS bit.
constexpr std::int64_t ClassicHeaderBits(const CanFrame& frame) {
  // SOF, identifier (11, or 11 + SRR + IDE + 18), RTR, IDE/r1, r0, DLC.
  return frame.extended ? 1 + 11 + 1 + 1 + 18 + 1 + 2 + 4 : 1 + 11 + 1 + 1 + 1 + 4;
}
constexpr std::int64_t FdArbitrationBits(const CanFrame& frame) {
  // SOF, identifier, RRS, IDE, FDF, res, BRS.
  return frame.extended ? 1 + 11 + 1 + 1 + 18 + 1 + 1 + 1 + 1 : 1 + 11 + 1 + 1 + 1 + 1 + 1;
}
constexpr std::int64_t PayloadBits(const CanFrame& frame) {
  return frame.remote ? 0 : 8 * std::int64_t{frame.length};
}
constexpr std::int64_t FdCrcBits(const CanFrame& frame) { return frame.length <= 16 ? 17 : 21; }
}  // namespace can_frame_bits_detail

constexpr CanFrameBits CountFrameBits(const CanFrame& frame) noexcept {
  namespace d = can_frame_bits_detail;
  if (!frame.fd) {
    // header, data, CRC 15, CRC delimiter, trailer.
    return {d::ClassicHeaderBits(frame) + d::PayloadBits(frame) + 15 + 1 + d::kTrailerBits, 0};
  }
  // CAN FD: arbitration at the nominal rate; then ESI, DLC, data, stuff count (4), CRC (17 up to
  // 16 bytes, else 21) and CRC delimiter at the data rate.
  const std::int64_t data_phase = 1 + 4 + d::PayloadBits(frame) + 4 + d::FdCrcBits(frame) + 1;
  if (frame.bit_rate_switch) return {d::FdArbitrationBits(frame) + d::kTrailerBits, data_phase};
  return {d::FdArbitrationBits(frame) + data_phase + d::kTrailerBits, 0};
}

constexpr CanFrameBits WorstCaseFrameBits(const CanFrame& frame) noexcept {
  namespace d = can_frame_bits_detail;
  CanFrameBits bits = CountFrameBits(frame);
  if (!frame.fd) {
    bits.nominal_bits += d::MaxStuffBits(d::ClassicHeaderBits(frame) + d::PayloadBits(frame) + 15);
    return bits;
  }
  const std::int64_t arbitration_stuff = d::MaxStuffBits(d::FdArbitrationBits(frame));
  // ESI, DLC and data stuffed dynamically; a fixed stuff bit before the stuff count and one per
  // four bits of the CRC.
  const std::int64_t data_stuff =
      d::MaxStuffBits(1 + 4 + d::PayloadBits(frame)) + 1 + d::CeilDiv(d::FdCrcBits(frame), 4);
  if (frame.bit_rate_switch) {
    bits.nominal_bits += arbitration_stuff;
    bits.data_bits += data_stuff;
  } else {
    bits.nominal_bits += arbitration_stuff + data_stuff;
  }
  return bits;
}

namespace can_frame_bits_detail {
// The bits of a classic frame from SOF to the end of the CRC sequence (the stuffed region), most
// significant first, as ISO 11898-1 sends them; returns how many (at most 1+32+4+64+15 = 116).
constexpr int ClassicStuffedRegion(const CanFrame& frame, bool (&bits)[128]) {
  int n = 0;
  const auto put = [&bits, &n](std::uint32_t value, int width) {
    for (int i = width - 1; i >= 0; --i) bits[n++] = ((value >> i) & 1u) != 0;
  };
  put(0, 1);  // SOF
  if (frame.extended) {
    put(frame.id >> 18, 11);
    put(1, 1);  // SRR
    put(1, 1);  // IDE
    put(frame.id & 0x3FFFFu, 18);
    put(frame.remote ? 1 : 0, 1);
    put(0, 2);  // r1, r0
  } else {
    put(frame.id, 11);
    put(frame.remote ? 1 : 0, 1);
    put(0, 2);  // IDE, r0
  }
  put(frame.length, 4);
  if (!frame.remote) {
    for (int b = 0; b < frame.length; ++b) put(frame.data[static_cast<std::size_t>(b)], 8);
  }
  // CRC-15 (polynomial 0x4599) over everything before it.
  std::uint32_t crc = 0;
  for (int i = 0; i < n; ++i) {
    const bool next = bits[i] != (((crc >> 14) & 1u) != 0);
    crc = (crc << 1) & 0x7FFFu;
    if (next) crc ^= 0x4599u;
  }
  put(crc, 15);
  return n;
}
}  // namespace can_frame_bits_detail

// The stuff bits a classic frame's own bit stream needs: after five equal bits the sender inserts
// one of the opposite value, which counts toward the next run.
constexpr std::int64_t ClassicStuffBits(const CanFrame& frame) noexcept {
  bool bits[128] = {};
  const int n = can_frame_bits_detail::ClassicStuffedRegion(frame, bits);
  std::int64_t stuffed = 0;
  int run = 0;
  bool last = false;
  for (int i = 0; i < n; ++i) {
    if (run > 0 && bits[i] == last) {
      ++run;
    } else {
      last = bits[i];
      run = 1;
    }
    if (run == 5) {
      ++stuffed;
      last = !last;
      run = 1;
    }
  }
  return stuffed;
}

constexpr CanFrameBits StuffedFrameBits(const CanFrame& frame) noexcept {
  if (frame.fd) return WorstCaseFrameBits(frame);
  CanFrameBits bits = CountFrameBits(frame);
  bits.nominal_bits += ClassicStuffBits(frame);
  return bits;
}

// Time on the bus in ns, rounded up. `data_bit_rate_bps` ≤ 0 means "same as nominal".
// Precondition: nominal_bit_rate_bps > 0.
constexpr std::int64_t FrameDurationNs(const CanFrameBits& bits, std::int64_t nominal_bit_rate_bps,
                                       std::int64_t data_bit_rate_bps) noexcept {
  namespace d = can_frame_bits_detail;
  constexpr std::int64_t kNsPerS = 1'000'000'000;
  const std::int64_t data_rate = data_bit_rate_bps > 0 ? data_bit_rate_bps : nominal_bit_rate_bps;
  return d::CeilDiv(bits.nominal_bits * kNsPerS, nominal_bit_rate_bps) +
         (bits.data_bits > 0 ? d::CeilDiv(bits.data_bits * kNsPerS, data_rate) : 0);
}

constexpr std::int64_t FrameDurationNs(const CanFrame& frame, std::int64_t nominal_bit_rate_bps,
                                       std::int64_t data_bit_rate_bps) noexcept {
  return FrameDurationNs(CountFrameBits(frame), nominal_bit_rate_bps, data_bit_rate_bps);
}

}  // namespace hrgbench::hw
