// CaptureThread against the real driver stack: GyroCanDevice on a VirtualCanBus (1 Mbit/s timed
// bus) with the simulated electronics GyroSimNode, all driven by a SimulationClock whose time
// moves while the capture thread waits in ReadSamples (tests/integration/gyro_can/gyro_rig.hpp).
// The sequencer's order of calls: StartRun (Configure → Excite → WaitReady → Release) in this
// thread, then the capture thread owns the device until Join.
//
// The simulator's failure modes (GyroSimFaults) give the device-side terminations and counts:
// dropped frames → sequence gaps, a stalled stream → kStalled, a shorted bus → kBusOff.

#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "gyro_rig.hpp"
#include "hrgbench/bench/capture/capture.hpp"

namespace hrgbench::bench {
namespace {

constexpr std::uint32_t kRateHz = 2000;

struct RigCapture {
  CaptureResult result;
  std::vector<hw::GyroSample> samples;
  std::int64_t t0_ns = 0;
};

RigCapture CaptureFromRig(const testing::GyroRigOptions& options, CaptureRun run) {
  testing::GyroRig rig(options);
  RigCapture out;
  out.t0_ns = rig.StartRun(kRateHz, {1.0, 0.2, 0.3});
  run.clock = &rig.clock;
  run.deadline_ns = out.t0_ns + 60'000'000'000;  // simulated time: only a guard against a hang
  SampleRing ring(1 << 15);
  CaptureThread capture;
  EXPECT_TRUE(capture.Start(*rig.device, ring, run).has_value());
  while (capture.Running()) {
    Drain(ring, out.samples);
    std::this_thread::yield();
  }
  out.result = capture.Join();
  Drain(ring, out.samples);
  EXPECT_TRUE(rig.device->Stop().has_value() ||
              out.result.termination == CaptureTermination::kBusOff);
  return out;
}

TEST(CaptureGyroCanTest, ARunOf4000SamplesArrivesCompleteWithTrueTimeStamps) {
  CaptureRun run;
  run.sample_count = 4000;  // 2 s at 2 kHz
  const RigCapture c = CaptureFromRig({}, run);
  EXPECT_EQ(c.result.termination, CaptureTermination::kCountReached) << c.result.Report();
  ASSERT_EQ(c.samples.size(), 4000u);
  for (std::uint32_t i = 0; i < c.samples.size(); ++i) {
    ASSERT_EQ(c.samples[i].seq, i);
    // t_ns is the electronics' sample clock mapped to the release stamp: seq / fs after t0.
    ASSERT_EQ(c.samples[i].t_ns, c.t0_ns + static_cast<std::int64_t>(i) * 500'000) << i;
  }
  EXPECT_EQ(c.result.sequence_gaps, 0u);
  EXPECT_EQ(c.result.ring_overruns, 0u);
  const hw::GyroCounters d = c.result.CounterDelta();
  EXPECT_GE(d.samples_decoded, 4000u);
  EXPECT_EQ(d.bad_frames, 0u);
  EXPECT_EQ(d.kernel_drops, 0u);
}

TEST(CaptureGyroCanTest, DroppedFramesAreGapsInTheRunAndInTheDeviceCounters) {
  testing::GyroRigOptions options;
  options.sim.faults.drop_every_nth_frame = 997;
  CaptureRun run;
  run.sample_count = 4000;
  const RigCapture c = CaptureFromRig(options, run);
  EXPECT_EQ(c.result.termination, CaptureTermination::kCountReached) << c.result.Report();
  EXPECT_GT(c.result.sequence_gaps, 0u);
  EXPECT_EQ(c.samples.size() + c.result.samples_missing, 4000u);
  // The capture's view and the driver's agree on the run's losses.
  EXPECT_EQ(c.result.sequence_gaps, c.result.CounterDelta().sequence_gaps);
}

TEST(CaptureGyroCanTest, AStreamThatStopsIsAStall) {
  testing::GyroRigOptions options;
  options.sim.faults.stall_after_samples = 1000;
  CaptureRun run;
  run.sample_count = 4000;
  run.max_silence_ns = 100'000'000;
  const RigCapture c = CaptureFromRig(options, run);
  EXPECT_EQ(c.result.termination, CaptureTermination::kStalled) << c.result.Report();
  EXPECT_GE(c.samples.size(), 999u);
  EXPECT_LE(c.samples.size(), 1001u);
  EXPECT_GT(c.result.read_timeouts, 0u);
}

TEST(CaptureGyroCanTest, BusOffEndsTheRun) {
  testing::GyroRigOptions options;
  options.sim.faults.bus_off_after_samples = 1500;
  CaptureRun run;
  run.sample_count = 4000;
  const RigCapture c = CaptureFromRig(options, run);
  EXPECT_EQ(c.result.termination, CaptureTermination::kBusOff) << c.result.Report();
  EXPECT_GE(c.samples.size(), 1400u);
  EXPECT_LE(c.samples.size(), 1501u);
  EXPECT_GT(c.result.CounterDelta().bus_errors, 0u);
}

}  // namespace
}  // namespace hrgbench::bench
