// STYLE rule 3: the capture loop does not allocate. tests/support/allocation_counter.hpp replaces
// the global operator new in this binary and counts per thread; the electronics' ReadSamples —
// called only by the capture thread — samples the capture thread's own count at every call. The
// count at the first read and at the last (after every batch has been pushed into the ring) must
// be equal while 100 000 samples stream through, and the consumer drains concurrently (its
// allocations are its own thread's and do not count).
//
// Twice: against FakeGyroElectronics, and (when the drivers are built) against the real driver
// stack: GyroCanDevice on a VirtualCanBus with the simulated electronics GyroSimNode, the
// SimulationClock driven from the capture thread's waits (tests/integration/gyro_can/gyro_rig.hpp).

#include <gtest/gtest.h>

#include <cstdio>
#include <thread>
#include <vector>

#include "allocation_counter.hpp"  // first: the replacement operator new (this TU only)
#include "fake_gyro_electronics.hpp"
#include "hrgbench/bench/capture/capture.hpp"

#ifdef HRGBENCH_CAPTURE_WITH_RIG
#include "gyro_rig.hpp"
#endif

namespace hrgbench::bench {
namespace {

using hrgbench::testing::thread_allocation_count;

std::int64_t CallingThreadAllocations() { return thread_allocation_count; }

// Runs a capture while this thread drains the ring into a vector reserved beforehand.
CaptureResult CaptureAndDrain(hw::GyroElectronics& electronics, const CaptureRun& run,
                              std::vector<hw::GyroSample>& samples,
                              std::size_t ring_capacity = 8192) {
  SampleRing ring(ring_capacity);
  CaptureThread capture;
  samples.reserve(run.sample_count + 1000);
  EXPECT_TRUE(capture.Start(electronics, ring, run).has_value());
  while (capture.Running()) {
    Drain(ring, samples);
    std::this_thread::yield();
  }
  CaptureResult result = capture.Join();
  Drain(ring, samples);
  return result;
}

TEST(CaptureAllocationTest, TheProbeSeesAnAllocationInTheCaptureThread) {
  hw::ManualClock clock(0);
  testing::FakeGyroScript script;
  script.allocate_in_read = true;
  testing::FakeGyroElectronics fake(clock, script);
  fake.probe = CallingThreadAllocations;
  CaptureRun run;
  run.sample_count = 1000;
  run.clock = &clock;
  std::vector<hw::GyroSample> samples;
  const CaptureResult result = CaptureAndDrain(fake, run, samples);
  EXPECT_GT(result.reads, 2u);
  EXPECT_EQ(fake.last_probe - fake.first_probe, static_cast<std::int64_t>(result.reads) - 1);
}

TEST(CaptureAllocationTest, OneHundredThousandSamplesFromTheFakeDoNotAllocate) {
  hw::ManualClock clock(0);
  testing::FakeGyroScript script;
  script.total_samples = 100'000;  // then kNotRunning: the last read comes after the last push
  script.max_per_read = 13;
  script.lost_seqs = {10, 20'000, 20'001};  // the gap path too
  testing::FakeGyroElectronics fake(clock, script);
  fake.probe = CallingThreadAllocations;
  CaptureRun run;
  run.sample_count = 200'000;
  run.clock = &clock;
  std::vector<hw::GyroSample> samples;
  const CaptureResult result = CaptureAndDrain(fake, run, samples);

  EXPECT_EQ(result.termination, CaptureTermination::kDeviceNotRunning);
  EXPECT_EQ(result.samples_read, 99'997u);
  EXPECT_EQ(result.sequence_gaps, 2u);
  EXPECT_GT(result.reads, 7'000u);
  EXPECT_EQ(fake.last_probe - fake.first_probe, 0) << "allocations in the capture loop";
}

#ifdef HRGBENCH_CAPTURE_WITH_RIG
// Forwards to the real device and samples the calling thread's allocation count on every read.
class ProbingElectronics final : public hw::GyroElectronics {
 public:
  explicit ProbingElectronics(hw::GyroElectronics& inner) : inner_(inner) {}
  std::expected<void, hw::GyroError> Configure(const hw::GyroConfig& c) override {
    return inner_.Configure(c);
  }
  std::expected<void, hw::GyroError> Excite(const hw::WaveState& w) override {
    return inner_.Excite(w);
  }
  std::expected<hw::GyroStatus, hw::GyroError> WaitReady(std::int64_t t) override {
    return inner_.WaitReady(t);
  }
  std::expected<std::int64_t, hw::GyroError> Release() override { return inner_.Release(); }
  std::expected<void, hw::GyroError> Stop() override { return inner_.Stop(); }
  std::expected<hw::GyroStatus, hw::GyroError> RequestStatus() override {
    return inner_.RequestStatus();
  }
  hw::GyroReadResult ReadSamples(std::span<hw::GyroSample> out,
                                 std::int64_t timeout_ns) noexcept override {
    last_count = thread_allocation_count;
    if (reads++ == 0) first_count = last_count;
    return inner_.ReadSamples(out, timeout_ns);
  }
  hw::GyroMode State() const noexcept override { return inner_.State(); }
  hw::GyroStatus LastStatus() const noexcept override { return inner_.LastStatus(); }
  hw::GyroCounters Counters() const noexcept override { return inner_.Counters(); }

  std::uint64_t reads = 0;
  std::int64_t first_count = 0;
  std::int64_t last_count = 0;

 private:
  hw::GyroElectronics& inner_;
};

TEST(CaptureAllocationTest, OneHundredThousandSamplesThroughGyroCanDeviceDoNotAllocate) {
  testing::GyroRigOptions options;
  options.sim.sigma = 1e-4;
  options.bit_rate_bps = 0;  // untimed bus: the software path, not the simulated wire
  testing::GyroRig rig(options);
  rig.StartRun(2000, {1.0, 0.2, 0.3});
  ProbingElectronics probing(*rig.device);
  CaptureRun run;
  run.sample_count = 100'000;
  run.clock = &rig.clock;
  // The simulated clock has no wall-clock meaning; a deadline guards against a hang only.
  run.deadline_ns = rig.clock.NowNs() + 200'000'000'000;
  std::vector<hw::GyroSample> samples;
  // A ring for the whole run: this test is about allocation, not about a slow consumer.
  const CaptureResult result = CaptureAndDrain(probing, run, samples, 1 << 17);

  EXPECT_EQ(result.termination, CaptureTermination::kCountReached) << result.Report();
  EXPECT_EQ(samples.size(), 100'000u);
  EXPECT_EQ(result.sequence_gaps, 0u);
  EXPECT_EQ(result.CounterDelta().bad_frames, 0u);
  // The last read returned the run's last sample; the count before it covers every earlier push.
  EXPECT_EQ(probing.last_count - probing.first_count, 0)
      << "allocations in the capture loop over GyroCanDevice";
  std::printf("[ info ] %s\n", result.Report().c_str());
}
#endif

}  // namespace
}  // namespace hrgbench::bench
