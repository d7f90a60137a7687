#pragma once
// ReplayGyroTraffic: a session's recorded CAN traffic played back through the host driver
// (GyroCanDevice over can_virtual::CanLogPlayback), so the driver rebuilds every run's samples
// from the recorded bytes exactly as it built them live.
//
// The recording drives the driver: each command the host sent to the node (in order) is turned
// back into the driver call that sends it — Configure, Excite, a status request (WaitReady with no
// time left while the wave is exciting, as a polling host; RequestStatus otherwise), Release,
// Stop — and the playback checks that the driver sends that very frame (retries included: a
// driver whose ack wait timed out then retries at the same recorded moment). After a Release the
// driver's samples are read until the next command; those are the run.
//
// Tokens: a driver numbers its commands from 0. A command whose token is 0 where the driver's
// next would be another is a new host process (a resumed session): a new driver takes over, as
// one did then. Any other token mismatch is a divergence.
//
// Failures the recording holds (an ack that never came, a rejected command, a fault) happen again
// and are listed in `notes`; they end nothing. A divergence (the driver sends what the host did
// not) ends the replay: `divergence` says where, the runs before it are kept.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "can_virtual/can_log_playback.hpp"
#include "gyro_can/gyro_can_device.hpp"
#include "gyro_can/gyro_protocol.hpp"
#include "hrgbench/hw/gyro_electronics.hpp"

namespace hrgbench::drivers::gyro_can {

struct ReplayedRun {
  std::uint64_t release_line = 0;  // the Release command's line in the recording
  std::int64_t release_t_ns = 0;   // t0 on the recording's time base (what Release returned)
  std::uint32_t sample_rate_hz = 0;
  FrameFormat format = FrameFormat::kClassic;
  // Every sample the driver delivered until the next command (the run and what followed it
  // until the host stopped the stream), in delivery order.
  std::vector<hw::GyroSample> samples;
  // The driver's counters over the run (from Release to the next command).
  hw::GyroCounters counters;
};

struct GyroReplay {
  std::vector<ReplayedRun> runs;
  std::uint64_t commands = 0;        // commands replayed (not counting retries)
  std::uint64_t frames_matched = 0;  // host frames the driver sent, retries included
  std::uint64_t frames_delivered = 0;
  int host_starts = 0;  // driver instances: 1, plus one per resume
  // Acks stamped after the host's wait that it took without resending (a descheduled host on a
  // loaded machine; can_log_playback.hpp "An answer taken late").
  std::uint64_t acks_taken_late = 0;
  // "line 812: timeout: release (token 13): no ack after 3 attempts of 50 ms": a call that
  // failed on the recorded traffic (as it failed live, when the driver is the one recorded).
  std::vector<std::string> notes;
  std::optional<std::string> divergence;
};

struct GyroReplayOptions {
  std::size_t read_batch = 256;  // samples per ReadSamples call
  // The host driver's waits as the station configured them ([gyro] ack_timeout_ms,
  // command_attempts): a retry happens again only if the replayed driver waits as long.
  std::int64_t ack_timeout_ns = GyroCanDeviceConfig{}.ack_timeout_ns;
  int command_attempts = GyroCanDeviceConfig{}.command_attempts;
  // The unit's node id: its commands and answers are replayed, other nodes' frames on a shared
  // bus are passed by (the driver filters them as it did live).
  NodeId node = 0;
};

GyroReplay ReplayGyroTraffic(can_virtual::PlaybackSource source,
                             const GyroReplayOptions& options = {});

}  // namespace hrgbench::drivers::gyro_can
