// The recorded traffic of a live host and the simulated electronics, played back through a fresh
// GyroCanDevice (ReplayGyroTraffic): the driver must rebuild the very samples it delivered live,
// gaps and retries included, follow a second host process (tokens from 0 again), and say where
// it stops matching the recording.

#include "gyro_can/gyro_traffic_replay.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <numbers>
#include <vector>

#include "gyro_can/gyro_codec.hpp"
#include "gyro_rig.hpp"
#include "hrgbench/hw/can_frame_text.hpp"

namespace hrgbench::testing {
namespace {

using drivers::can_virtual::PlaybackFrame;
using drivers::gyro_can::GyroReplay;
using hw::GyroSample;

const hw::WaveState kWave{1.0, -0.4, std::numbers::pi / 7};

struct LiveRun {
  std::int64_t t0 = 0;
  std::vector<GyroSample> samples;
};

// A rig with a bus monitor that sees every frame (both directions), as the bench's CAN log does.
struct RecordedRig {
  explicit RecordedRig(const GyroRigOptions& options) : rig(options) {
    drivers::can_virtual::VirtualCanEndpointOptions monitor_options;
    monitor_options.queue_capacity = std::size_t{1} << 20;
    monitor = rig.bus->CreateEndpoint(monitor_options);
  }

  // Configure, excite, wait, release, read `n` samples, status, stop: the bench's run.
  LiveRun Run(std::size_t n) {
    LiveRun run;
    run.t0 = rig.StartRun(1000, kWave);
    std::vector<GyroSample> chunk(64);
    while (run.samples.size() < n) {
      const hw::GyroReadResult r = rig.device->ReadSamples(chunk, 100'000'000);
      run.samples.insert(run.samples.end(), chunk.begin(),
                         chunk.begin() + static_cast<std::ptrdiff_t>(r.count));
      if (r.status != hw::GyroReadStatus::kOk) break;
    }
    EXPECT_TRUE(rig.device->RequestStatus().has_value());
    EXPECT_TRUE(rig.device->Stop().has_value());
    return run;
  }

  // Everything the monitor saw, numbered like the lines of a log.
  void Drain(std::vector<PlaybackFrame>& log) {
    hw::CanFrame frame;
    hw::ReceiveInfo info;
    while (monitor->Receive(&frame, 0, &info) == hw::CanStatus::kOk) {
      log.push_back({info.timestamp_ns, frame, log.size() + 1});
    }
  }

  GyroRig rig;
  std::unique_ptr<drivers::can_virtual::VirtualCanEndpoint> monitor;
};

GyroReplay Replay(const std::vector<PlaybackFrame>& log) {
  std::size_t next = 0;
  return drivers::gyro_can::ReplayGyroTraffic([&]() -> std::optional<PlaybackFrame> {
    if (next == log.size()) return std::nullopt;
    return log[next++];
  });
}

// The replayed run holds the live samples first (it also holds what came after the host had
// enough, until its Stop), bit for bit and on the same time grid relative to the release.
void ExpectSameSamples(const LiveRun& live, const drivers::gyro_can::ReplayedRun& replayed) {
  ASSERT_GE(replayed.samples.size(), live.samples.size());
  for (std::size_t k = 0; k < live.samples.size(); ++k) {
    const GyroSample& a = live.samples[k];
    const GyroSample& b = replayed.samples[k];
    ASSERT_EQ(a.seq, b.seq) << "sample " << k;
    ASSERT_EQ(a.t_ns - live.t0, b.t_ns - replayed.release_t_ns) << "sample " << k;
    for (int c = 0; c < 4; ++c)
      ASSERT_EQ(std::bit_cast<std::uint64_t>(a.y[c]), std::bit_cast<std::uint64_t>(b.y[c]))
          << "sample " << k << " y" << c + 1;
  }
}

TEST(GyroTrafficReplay, RebuildsEveryLiveSampleWithTheSameGapsAndRetries) {
  GyroRigOptions options;
  options.sim.sigma = 1e-4;
  options.sim.faults.ignore_commands = 1;  // the first Configure is retried
  RecordedRig recorded(options);
  std::vector<LiveRun> live;
  live.push_back(recorded.Run(1500));
  // Three sample frames lost at the source in run 2: two samples, one break.
  const std::uint64_t lost_before = recorded.rig.device->Counters().samples_lost;
  LiveRun second;
  second.t0 = recorded.rig.StartRun(1000, kWave);
  std::vector<GyroSample> chunk(64);
  bool dropped = false;
  while (second.samples.size() < 1200) {
    if (!dropped && second.samples.size() >= 600) {
      recorded.rig.node->faults().drop_sample_frames = 3;
      dropped = true;
    }
    const hw::GyroReadResult r = recorded.rig.device->ReadSamples(chunk, 100'000'000);
    second.samples.insert(second.samples.end(), chunk.begin(),
                          chunk.begin() + static_cast<std::ptrdiff_t>(r.count));
    ASSERT_EQ(r.status, hw::GyroReadStatus::kOk);
  }
  ASSERT_TRUE(recorded.rig.device->Stop().has_value());
  live.push_back(second);
  ASSERT_EQ(recorded.rig.device->Counters().samples_lost - lost_before, 2u);
  EXPECT_EQ(recorded.rig.device->Counters().command_retries, 1u);

  std::vector<PlaybackFrame> log;
  recorded.Drain(log);
  const GyroReplay replay = Replay(log);
  ASSERT_FALSE(replay.divergence) << *replay.divergence;
  EXPECT_TRUE(replay.notes.empty());
  EXPECT_EQ(replay.host_starts, 1);
  ASSERT_EQ(replay.runs.size(), 2u);
  ExpectSameSamples(live[0], replay.runs[0]);
  ExpectSameSamples(live[1], replay.runs[1]);
  EXPECT_EQ(replay.runs[0].counters.samples_lost, 0u);
  EXPECT_EQ(replay.runs[1].counters.samples_lost, 2u);
  EXPECT_EQ(replay.runs[1].counters.sequence_gaps, 1u);
  // Every frame the host sent was sent again, the retry included.
  std::uint64_t host_frames = 0;
  for (const PlaybackFrame& f : log)
    host_frames += drivers::gyro_can::IsCommandId(f.frame.id) ? 1 : 0;
  EXPECT_EQ(replay.frames_matched, host_frames);
}

// Two host processes one after the other (a resumed session): each driver counts its tokens
// from 0, the second starts while the electronics are still configured. Their runs of `first` and
// `second` samples, and the log of both.
struct TwoHosts {
  LiveRun first, second;
  std::vector<PlaybackFrame> log;
};

TwoHosts RecordTwoHosts(std::size_t first, std::size_t second) {
  GyroRigOptions options;
  options.sim.sigma = 1e-4;
  RecordedRig recorded(options);
  TwoHosts out;
  out.first = recorded.Run(first);
  auto restarted = drivers::gyro_can::GyroCanDevice::Create(*recorded.rig.host_endpoint, [&] {
    drivers::gyro_can::GyroCanDeviceConfig config;
    config.clock = &recorded.rig.clock;
    return config;
  }());
  EXPECT_TRUE(restarted.has_value());
  if (!restarted) return out;
  recorded.rig.device = std::move(*restarted);
  out.second = recorded.Run(second);
  recorded.Drain(out.log);
  return out;
}

TEST(GyroTrafficReplay, ASecondHostProcessIsFollowed) {
  const TwoHosts recorded = RecordTwoHosts(500, 700);
  const LiveRun& first = recorded.first;
  const LiveRun& second = recorded.second;
  const GyroReplay replay = Replay(recorded.log);
  ASSERT_FALSE(replay.divergence) << *replay.divergence;
  EXPECT_EQ(replay.host_starts, 2);
  ASSERT_EQ(replay.runs.size(), 2u);
  ExpectSameSamples(first, replay.runs[0]);
  ExpectSameSamples(second, replay.runs[1]);
}

// A host descheduled past its ack deadline (a loaded machine, a process just started) takes the
// Ack already queued, stamped after the deadline, and does not resend: the replay must follow it,
// not resend a Configure the recording does not have (BenchProgram.FixtureKilledMidRunResumes-
// EveryUnit diverged so at load 8-13, on the resumed host's first Configure).
TEST(GyroTrafficReplay, AnAckStampedPastTheDeadlineThatTheHostTookIsFollowed) {
  TwoHosts recorded = RecordTwoHosts(400, 400);
  const LiveRun& first = recorded.first;
  const LiveRun& second = recorded.second;
  std::vector<PlaybackFrame>& log = recorded.log;
  // The second host's Configure: its Ack stamped three ack timeouts late.
  const std::int64_t timeout_ns = drivers::gyro_can::GyroCanDeviceConfig{}.ack_timeout_ns;
  std::size_t configures = 0;
  std::int64_t configure_stamp = 0;
  std::uint64_t late_line = 0;
  for (PlaybackFrame& f : log) {
    if (f.frame.id == drivers::gyro_can::can_id::kConfigure && ++configures == 2)
      configure_stamp = f.stamp_ns;
    if (configure_stamp != 0 && late_line == 0 && f.frame.id == drivers::gyro_can::can_id::kAck) {
      f.stamp_ns = configure_stamp + 3 * timeout_ns;
      late_line = f.line;
    }
  }
  ASSERT_NE(late_line, 0u);
  const GyroReplay replay = Replay(log);
  ASSERT_FALSE(replay.divergence) << *replay.divergence;
  EXPECT_TRUE(replay.notes.empty()) << replay.notes.front();
  EXPECT_EQ(replay.acks_taken_late, 1u);
  EXPECT_EQ(replay.host_starts, 2);
  ASSERT_EQ(replay.runs.size(), 2u);
  ExpectSameSamples(first, replay.runs[0]);
  ExpectSameSamples(second, replay.runs[1]);
}

TEST(GyroTrafficReplay, ADriverThatSendsOtherwiseIsNamedAtTheLine) {
  RecordedRig recorded(GyroRigOptions{});
  const LiveRun first = recorded.Run(300);
  recorded.Run(300);
  std::vector<PlaybackFrame> log;
  recorded.Drain(log);
  // The second Configure asked for a status rate this driver never asks for: what a driver
  // change that altered the command would look like against the recording.
  std::size_t configures = 0;
  std::uint64_t changed_line = 0;
  std::string recorded_text;
  for (PlaybackFrame& f : log) {
    if (f.frame.id != drivers::gyro_can::can_id::kConfigure || ++configures != 2) continue;
    drivers::gyro_can::ConfigureCommand c;
    ASSERT_EQ(drivers::gyro_can::DecodeConfigure(f.frame, 0, &c),
              drivers::gyro_can::DecodeStatus::kOk);
    c.status_rate_hz = 3;
    f.frame = drivers::gyro_can::EncodeConfigure(0, c);
    changed_line = f.line;
    recorded_text = hw::CanFrameToString(f.frame);
  }
  ASSERT_NE(changed_line, 0u);
  const GyroReplay replay = Replay(log);
  ASSERT_TRUE(replay.divergence);
  EXPECT_NE(replay.divergence->find("line " + std::to_string(changed_line) + " of the log has " +
                                    recorded_text),
            std::string::npos)
      << *replay.divergence;
  // What came before the divergence stands.
  ASSERT_EQ(replay.runs.size(), 1u);
  ExpectSameSamples(first, replay.runs[0]);
}

}  // namespace
}  // namespace hrgbench::testing
