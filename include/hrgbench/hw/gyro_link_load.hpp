#pragma once
// The share of its CAN bus one gyro's link takes, for planning (`hrg-bench check`): the frames the
// electronics' protocol sends per second at a sample rate, each at its worst-case stuffed length
// (can_frame_bits.hpp). The frame shapes are protocol v2's (drivers/gyro_can/README.md "Bus load";
// drivers/gyro_can/gyro_protocol.hpp static_asserts they agree):
//   classic: two 8-byte frames per sample;  CAN FD: one 64-byte frame (BRS) per five samples;
//   the reference phase (optional, planned as sent): one 8-byte frame per five samples;
//   status: one 8-byte frame at the status rate (10 Hz).
// At 1 Mbit/s, 1 kHz classic is 27.0 % + 2.7 % + 0.1 %.

#include <cstdint>

#include "hrgbench/hw/can_frame_bits.hpp"

namespace hrgbench::hw {

inline constexpr int kGyroClassicFramesPerSample = 2;
inline constexpr std::uint8_t kGyroClassicFrameBytes = 8;  // samples, reference phase, status
inline constexpr int kGyroSamplesPerFdFrame = 5;
inline constexpr std::uint8_t kGyroFdFrameBytes = 64;
inline constexpr int kGyroSamplesPerReferencePhase = 5;
inline constexpr std::uint32_t kGyroStatusRateHz = 10;

// A plan is refused above this share of the bus: the rest is for commands, their retries, error
// frames and recovery, and any other node (CiA practice keeps a CAN bus below 70-80 %).
inline constexpr double kMaxPlannedBusShare = 0.70;

struct GyroLinkPlan {
  std::uint32_t sample_rate_hz = 1000;
  bool can_fd = false;
  bool reference_phase = true;  // electronics that report it; planned as sent
  std::int64_t nominal_bit_rate_bps = 1'000'000;
  std::int64_t data_bit_rate_bps = 0;  // FD data phase; ≤ 0: the nominal rate
};

struct GyroLinkLoad {
  double frames_per_s = 0.0;
  double bus_share = 0.0;  // fraction of the bus's time, worst-case stuffing
};

constexpr GyroLinkLoad WorstCaseLinkLoad(const GyroLinkPlan& plan) noexcept {
  CanFrame classic;
  classic.length = kGyroClassicFrameBytes;
  CanFrame fd;
  fd.fd = true;
  fd.bit_rate_switch = true;
  fd.length = kGyroFdFrameBytes;
  const auto seconds = [&plan](const CanFrame& frame) {
    return static_cast<double>(FrameDurationNs(WorstCaseFrameBits(frame), plan.nominal_bit_rate_bps,
                                               plan.data_bit_rate_bps)) *
           1e-9;
  };
  const double rate = plan.sample_rate_hz;
  const double sample_frames =
      plan.can_fd ? rate / kGyroSamplesPerFdFrame : rate * kGyroClassicFramesPerSample;
  const double phase_frames = plan.reference_phase ? rate / kGyroSamplesPerReferencePhase : 0.0;
  const double status_frames = kGyroStatusRateHz;
  GyroLinkLoad load;
  load.frames_per_s = sample_frames + phase_frames + status_frames;
  load.bus_share = sample_frames * seconds(plan.can_fd ? fd : classic) +
                   (phase_frames + status_frames) * seconds(classic);
  return load;
}

}  // namespace hrgbench::hw
