// CaptureThread against FakeGyroElectronics: every termination reason, every count, the data
// (order and content) the consumer drains while the capture runs, and Start's refusals.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "fake_gyro_electronics.hpp"
#include "hrgbench/bench/capture/capture.hpp"

namespace hrgbench::bench {
namespace {

using testing::FakeGyroElectronics;
using testing::FakeGyroScript;
using testing::FakeY;

// Runs one capture to its end while draining the ring in this thread, as the sequencer would.
struct Captured {
  CaptureResult result;
  std::vector<hw::GyroSample> samples;
};
Captured CaptureAll(FakeGyroElectronics& fake, SampleRing& ring, const CaptureRun& run,
                    bool drain = true) {
  CaptureThread capture(16);
  Captured out;
  auto started = capture.Start(fake, ring, run);
  EXPECT_TRUE(started.has_value()) << (started ? "" : started.error().message);
  while (capture.Running()) {
    if (drain) Drain(ring, out.samples);
    std::this_thread::yield();
  }
  out.result = capture.Join();
  if (drain) Drain(ring, out.samples);
  return out;
}

bool SampleIsIntact(const hw::GyroSample& s, std::int64_t t0_ns) {
  bool ok = s.t_ns == t0_ns + static_cast<std::int64_t>(s.seq) * 1'000'000;
  for (int k = 0; k < 4; ++k) ok = ok && s.y[k] == FakeY(s.seq, k);
  return ok;
}

TEST(CaptureThreadTest, CountStopDeliversExactlyTheRunsSamplesInOrder) {
  hw::ManualClock clock(5'000'000'000);
  FakeGyroScript script;
  script.max_per_read = 7;  // reads smaller than the batch
  FakeGyroElectronics fake(clock, script);
  // The fake produces as fast as the CPU allows, faster than this consumer drains: a ring for the
  // whole run keeps the test about order and content (overruns have their own test).
  SampleRing ring(16384);
  CaptureRun run;
  run.sample_count = 10'000;
  run.clock = &clock;
  const Captured c = CaptureAll(fake, ring, run);

  EXPECT_EQ(c.result.termination, CaptureTermination::kCountReached);
  ASSERT_EQ(c.samples.size(), 10'000u);
  for (std::uint32_t i = 0; i < c.samples.size(); ++i) {
    ASSERT_EQ(c.samples[i].seq, i);
    ASSERT_TRUE(SampleIsIntact(c.samples[i], fake.t0_ns())) << "seq " << i;
  }
  EXPECT_EQ(c.result.samples_pushed, 10'000u);
  EXPECT_EQ(c.result.samples_after_end, c.result.samples_read - 10'000u);
  EXPECT_EQ(c.result.sequence_gaps, 0u);
  EXPECT_EQ(c.result.first_seq, 0u);
  EXPECT_EQ(c.result.last_seq, 9'999u);
  EXPECT_EQ(c.result.last_t_ns, fake.t0_ns() + 9'999'000'000);
  EXPECT_LE(c.result.max_batch, 7u);
  EXPECT_EQ(c.result.started_ns, 5'000'000'000);
  EXPECT_EQ(c.result.CounterDelta().samples_decoded, c.result.samples_read);
  EXPECT_NE(c.result.Report().find("count reached"), std::string::npos) << c.result.Report();
}

TEST(CaptureThreadTest, DeadlineStopsTheRunOnTheRunsClock) {
  hw::ManualClock clock(0);
  FakeGyroElectronics fake(clock, {});
  SampleRing ring(1024);
  CaptureRun run;
  run.deadline_ns = 500'000'000;  // 500 samples at 1 kHz on the fake's clock
  run.clock = &clock;
  const Captured c = CaptureAll(fake, ring, run);
  EXPECT_EQ(c.result.termination, CaptureTermination::kDeadline);
  // The fake advances the clock per sample; a read of up to 16 samples may overshoot by one batch.
  EXPECT_GE(c.samples.size(), 500u);
  EXPECT_LE(c.samples.size(), 516u);
}

TEST(CaptureThreadTest, GapsAndRegressionsAreCountedAndNotPassedOn) {
  hw::ManualClock clock(0);
  FakeGyroScript script;
  script.lost_seqs = {0, 5, 6, 100};  // the first sample of the run is lost too
  script.duplicated_seqs = {50};
  FakeGyroElectronics fake(clock, script);
  SampleRing ring(1024);
  CaptureRun run;
  run.sample_count = 1000;
  run.clock = &clock;
  const Captured c = CaptureAll(fake, ring, run);
  EXPECT_EQ(c.result.termination, CaptureTermination::kCountReached);
  EXPECT_EQ(c.result.sequence_gaps, 3u);  // before 1, 5-6, 100
  EXPECT_EQ(c.result.samples_missing, 4u);
  EXPECT_EQ(c.result.sequence_regressions, 1u);
  EXPECT_EQ(c.samples.size(), 996u);
  EXPECT_EQ(c.result.first_seq, 1u);
  for (std::size_t i = 1; i < c.samples.size(); ++i) {
    ASSERT_GT(c.samples[i].seq, c.samples[i - 1].seq);
  }
  // The driver's own view of the same run.
  EXPECT_EQ(c.result.CounterDelta().sequence_gaps, 4u);
  EXPECT_EQ(c.result.CounterDelta().samples_lost, 4u);
}

TEST(CaptureThreadTest, ALostLastSampleStillEndsTheRunAtTheNextOne) {
  hw::ManualClock clock(0);
  FakeGyroScript script;
  script.lost_seqs = {999};
  script.max_per_read = 1;
  FakeGyroElectronics fake(clock, script);
  SampleRing ring(2048);
  CaptureRun run;
  run.sample_count = 1000;
  run.clock = &clock;
  const Captured c = CaptureAll(fake, ring, run);
  EXPECT_EQ(c.result.termination, CaptureTermination::kCountReached);
  EXPECT_EQ(c.samples.size(), 999u);
  EXPECT_EQ(c.result.samples_missing, 1u);
  EXPECT_EQ(c.result.samples_after_end, 1u);
  EXPECT_EQ(c.result.last_seq, 998u);
}

TEST(CaptureThreadTest, DeviceEndsAreTerminationReasons) {
  struct Case {
    hw::GyroReadStatus status;
    CaptureTermination termination;
  };
  for (const Case& k :
       {Case{hw::GyroReadStatus::kNotRunning, CaptureTermination::kDeviceNotRunning},
        Case{hw::GyroReadStatus::kBusOff, CaptureTermination::kBusOff},
        Case{hw::GyroReadStatus::kError, CaptureTermination::kDeviceError}}) {
    hw::ManualClock clock(0);
    FakeGyroScript script;
    script.total_samples = 300;
    script.end_status = k.status;
    FakeGyroElectronics fake(clock, script);
    SampleRing ring(1024);
    CaptureRun run;
    run.sample_count = 1000;
    run.clock = &clock;
    const Captured c = CaptureAll(fake, ring, run);
    EXPECT_EQ(c.result.termination, k.termination) << ToString(k.termination);
    EXPECT_EQ(c.samples.size(), 300u);
  }
}

TEST(CaptureThreadTest, SilenceLongerThanTheLimitIsAStall) {
  hw::ManualClock clock(0);
  FakeGyroScript script;
  script.total_samples = 100;
  script.end_status = hw::GyroReadStatus::kTimeout;
  FakeGyroElectronics fake(clock, script);
  SampleRing ring(1024);
  CaptureRun run;
  run.sample_count = 1000;
  run.clock = &clock;
  run.read_timeout_ns = 10'000'000;
  run.max_silence_ns = 50'000'000;
  const Captured c = CaptureAll(fake, ring, run);
  EXPECT_EQ(c.result.termination, CaptureTermination::kStalled);
  EXPECT_EQ(c.result.read_timeouts, 5u);
  EXPECT_EQ(c.result.CounterDelta().timeouts, 5u);
  EXPECT_EQ(c.samples.size(), 100u);
}

TEST(CaptureThreadTest, AFullRingRefusesAndCountsOverruns) {
  hw::ManualClock clock(0);
  FakeGyroElectronics fake(clock, {});
  SampleRing ring(256);
  CaptureRun run;
  run.sample_count = 1000;
  run.clock = &clock;
  const Captured c = CaptureAll(fake, ring, run, /*drain=*/false);
  EXPECT_EQ(c.result.termination, CaptureTermination::kCountReached);
  EXPECT_EQ(c.result.samples_pushed, 256u);
  EXPECT_EQ(c.result.ring_overruns, 744u);
  EXPECT_EQ(ring.Overruns(), 744u);
  EXPECT_EQ(c.result.ring_high_water, 256u);
  EXPECT_EQ(c.result.last_seq, 255u);  // the oldest are kept
}

TEST(CaptureThreadTest, RequestStopAndTheExternalFlagEndTheRun) {
  for (bool external : {false, true}) {
    hw::ManualClock clock(0);
    FakeGyroScript script;
    script.total_samples = 10;
    script.end_status = hw::GyroReadStatus::kTimeout;  // then silence, in real time too
    script.real_sleep_on_timeout_ns = 1'000'000;
    FakeGyroElectronics fake(clock, script);
    SampleRing ring(64);
    std::atomic<bool> ctrl_c{false};
    CaptureRun run;
    run.deadline_ns = INT64_MAX;
    run.clock = &clock;
    run.external_stop = &ctrl_c;
    CaptureThread capture;
    ASSERT_TRUE(capture.Start(fake, ring, run).has_value());
    while (capture.Progress().samples_pushed < 10) std::this_thread::yield();
    EXPECT_TRUE(capture.Running());
    if (external) {
      ctrl_c.store(true);
    } else {
      capture.RequestStop();
    }
    const CaptureResult result = capture.Join();
    EXPECT_FALSE(capture.Running());
    EXPECT_EQ(result.termination, CaptureTermination::kStopRequested);
    EXPECT_EQ(result.samples_pushed, 10u);
  }
}

TEST(CaptureThreadTest, OneCaptureThreadServesSeveralRuns) {
  CaptureThread capture;
  for (int r = 0; r < 3; ++r) {
    hw::ManualClock clock(0);
    FakeGyroElectronics fake(clock, {});
    SampleRing ring(4096);
    CaptureRun run;
    run.sample_count = 2000;
    run.clock = &clock;
    ASSERT_TRUE(capture.Start(fake, ring, run).has_value());
    const CaptureResult result = capture.Join();
    EXPECT_EQ(result.termination, CaptureTermination::kCountReached);
    EXPECT_EQ(result.samples_pushed, 2000u);
    EXPECT_EQ(ring.Size(), 2000u);
  }
}

TEST(CaptureThreadTest, StartRefusesWhatItCannotRun) {
  hw::ManualClock clock(0);
  FakeGyroScript script;
  script.total_samples = 0;
  script.end_status = hw::GyroReadStatus::kTimeout;
  script.real_sleep_on_timeout_ns = 1'000'000;
  FakeGyroElectronics fake(clock, script);
  SampleRing ring(64);
  CaptureThread capture;

  EXPECT_EQ(capture.Join().termination, CaptureTermination::kNotStarted);
  EXPECT_EQ(CaptureResult{}.Report(), "Capture was not started.");

  CaptureRun unbounded;  // neither count nor deadline
  auto refused = capture.Start(fake, ring, unbounded);
  ASSERT_FALSE(refused.has_value());
  EXPECT_EQ(refused.error().code, CaptureError::Code::kInvalidArgument);
  EXPECT_NE(refused.error().message.find("stop condition"), std::string::npos);

  CaptureRun bad = unbounded;
  bad.sample_count = 10;
  bad.read_timeout_ns = 0;
  EXPECT_FALSE(capture.Start(fake, ring, bad).has_value());
  bad.read_timeout_ns = 1'000'000;
  bad.realtime.cpu = -2;
  EXPECT_FALSE(capture.Start(fake, ring, bad).has_value());
  bad.realtime.cpu = -1;
  bad.realtime.priority = -1;
  EXPECT_FALSE(capture.Start(fake, ring, bad).has_value());

  CaptureRun run;
  run.sample_count = 10;
  run.clock = &clock;
  ASSERT_TRUE(capture.Start(fake, ring, run).has_value());
  auto again = capture.Start(fake, ring, run);
  ASSERT_FALSE(again.has_value());
  EXPECT_EQ(again.error().code, CaptureError::Code::kAlreadyRunning);
  capture.RequestStop();
  EXPECT_EQ(capture.Join().termination, CaptureTermination::kStopRequested);
}

TEST(CaptureThreadTest, DestroyingARunningCaptureStopsIt) {
  hw::ManualClock clock(0);
  FakeGyroScript script;
  script.total_samples = 0;
  script.end_status = hw::GyroReadStatus::kTimeout;
  script.real_sleep_on_timeout_ns = 1'000'000;
  FakeGyroElectronics fake(clock, script);
  SampleRing ring(64);
  CaptureRun run;
  run.deadline_ns = INT64_MAX;
  run.clock = &clock;
  {
    CaptureThread capture;
    ASSERT_TRUE(capture.Start(fake, ring, run).has_value());
  }  // must not hang or terminate
  SUCCEED();
}

}  // namespace
}  // namespace hrgbench::bench
