// GyroCanDevice against the simulated electronics (GyroSimNode) over the virtual bus with 1 Mbit/s
// bit timing: the state machine, a 10 s run at 1 kHz compared with the model, CAN FD packing, and
// every failure mode the simulator can inject.

#include <gtest/gtest.h>

#include <chrono>
#include <numbers>
#include <vector>

#include "gyro_rig.hpp"
#include "hrgbench/estimator/simulation.hpp"
#include "sim/carrier_simulation.hpp"

namespace hrgbench::testing {
namespace {

using hw::GyroErrorCode;
using hw::GyroMode;
using hw::GyroReadStatus;
using hw::GyroSample;

drivers::sim::GyroSimOptions NoiseFreeModel() {
  drivers::sim::GyroSimOptions o;
  o.delta << -0.001, 0.3, 2e-4, -1e-4, 3e-4, -2e-4;
  o.xi << 0.01, -0.004, 0.003, 0.002;
  o.sigma = 0.0;
  return o;
}

const hw::WaveState kWave{1.0, -0.4, std::numbers::pi / 7};

// Reads until `n` samples or a non-ok status; returns them.
std::vector<GyroSample> ReadN(hw::GyroElectronics& device, std::size_t n,
                              GyroReadStatus* last = nullptr,
                              std::int64_t timeout_ns = 100'000'000) {
  std::vector<GyroSample> all;
  all.reserve(n);
  std::vector<GyroSample> chunk(64);
  while (all.size() < n) {
    const std::size_t want = std::min<std::size_t>(chunk.size(), n - all.size());
    const hw::GyroReadResult r = device.ReadSamples(std::span(chunk.data(), want), timeout_ns);
    all.insert(all.end(), chunk.begin(), chunk.begin() + static_cast<std::ptrdiff_t>(r.count));
    if (r.status != GyroReadStatus::kOk) {
      if (last != nullptr) *last = r.status;
      return all;
    }
  }
  if (last != nullptr) *last = GyroReadStatus::kOk;
  return all;
}

// The model's y at sample k for the wave as quantised on the wire.
estimator::Observation ModelY(const drivers::sim::GyroSimOptions& o, double omega, double t_s) {
  const estimator::Orbit orbit{std::round(kWave.a / 1e-4) * 1e-4, std::round(kWave.b / 1e-4) * 1e-4,
                               std::round(kWave.theta_rad / 1e-4) * 1e-4, 0.0};
  const estimator::State x =
      estimator::PropagateExact(omega, o.delta, estimator::OrbitToState(orbit), t_s);
  return (estimator::Matrix4::Identity() + estimator::DistortionMatrix(o.xi)) * x;
}

TEST(GyroCanDeviceTest, TenSecondsAtOneKilohertzMatchTheModel) {
  GyroRigOptions options;
  options.sim = NoiseFreeModel();
  GyroRig rig(options);
  EXPECT_EQ(rig.device->State(), GyroMode::kIdle);
  const auto wall_start = std::chrono::steady_clock::now();
  const std::int64_t t0 = rig.StartRun(1000, kWave);
  EXPECT_EQ(rig.device->State(), GyroMode::kFreeRun);
  const std::vector<GyroSample> samples = ReadN(*rig.device, 10'000);
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  ASSERT_EQ(samples.size(), 10'000u);
  double worst = 0.0;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    ASSERT_EQ(samples[k].seq, k);
    ASSERT_EQ(samples[k].t_ns, t0 + static_cast<std::int64_t>(k) * 1'000'000);
    const estimator::Observation y =
        ModelY(options.sim, options.omega_rad_s, 1e-3 * static_cast<double>(k));
    for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(samples[k].y[c] - y(c)));
  }
  // Quantisation only: half an LSB (plus rounding of the closed form).
  EXPECT_LE(worst, drivers::gyro_can::kSampleLsb / 2 + 1e-12);
  // Samples arrive on time over a 1 Mbit/s bus: the stream ends ~10 s after t0, not later.
  EXPECT_LT(rig.clock.NowNs() - t0, 10'100'000'000);
  const hw::GyroCounters c = rig.device->Counters();
  EXPECT_EQ(c.samples_decoded, 10'000u);
  EXPECT_EQ(c.sequence_gaps, 0u);
  EXPECT_EQ(c.samples_lost, 0u);
  EXPECT_EQ(c.bad_frames, 0u);
  EXPECT_EQ(c.kernel_drops, 0u);
  EXPECT_EQ(c.command_retries, 0u);
  ASSERT_TRUE(rig.device->Stop().has_value());
  EXPECT_EQ(rig.device->State(), GyroMode::kStopped);
  const hw::GyroStatus status = rig.device->LastStatus();
  EXPECT_NEAR(status.resonant_frequency_hz, 5000.0, 1e-9);
  EXPECT_NEAR(status.temperature_c, 25.0, 1e-9);
  std::printf("[ info ] 10 s of 1 kHz samples (20 000 frames) in %.3f s wall time\n", wall_s);
}

// Two units on one bus (gyro CAN protocol v2): nodes 1 and 2, each with its own truth, each host
// driver talking to its own node. Commands to node 1 leave node 2 untouched; both stream at once
// and each driver gets its own node's samples (its model's y to half an LSB), none of the other's
// frames (its filter) and no loss (2 × 2000 frames/s is 44 % of the 1 Mbit/s bus).
TEST(GyroCanDeviceTest, TwoNodesOnOneBusEachHostHearsItsOwn) {
  GyroRigOptions options;
  options.sim = NoiseFreeModel();
  options.sim.node = 1;
  options.device.node = 1;
  GyroRig rig(options);
  drivers::sim::GyroSimOptions other = NoiseFreeModel();
  other.node = 2;
  other.xi << 0.02, -0.01, 0.005, 0.0;
  auto other_endpoint = rig.bus->CreateEndpoint();
  drivers::sim::GyroSimNode other_node(*other_endpoint, rig.clock, other,
                                       [&rig] { return rig.omega_rad_s; });
  rig.clock.AddParticipant(&other_node);
  auto other_host = rig.bus->CreateEndpoint();
  drivers::gyro_can::GyroCanDeviceConfig other_config;
  other_config.clock = &rig.clock;
  other_config.node = 2;
  auto other_device = drivers::gyro_can::GyroCanDevice::Create(*other_host, other_config);
  ASSERT_TRUE(other_device.has_value());

  const std::int64_t t0 = rig.StartRun(1000, kWave);
  EXPECT_EQ(other_node.Statistics().commands, 0u);  // node 1's commands are not node 2's
  ASSERT_TRUE((*other_device)->Configure({1000}).has_value());
  ASSERT_TRUE((*other_device)->Excite(kWave).has_value());
  ASSERT_TRUE((*other_device)->WaitReady(2'000'000'000).has_value());
  const auto t0_other = (*other_device)->Release();
  ASSERT_TRUE(t0_other.has_value());

  std::vector<GyroSample> mine, theirs;
  while (mine.size() < 2000 || theirs.size() < 2000) {
    for (auto [device, into] :
         {std::pair{rig.device.get(), &mine}, std::pair{other_device->get(), &theirs}}) {
      if (into->size() >= 2000) continue;
      const std::vector<GyroSample> chunk = ReadN(*device, 50);
      ASSERT_EQ(chunk.size(), 50u);
      into->insert(into->end(), chunk.begin(), chunk.end());
    }
  }
  double worst = 0.0, worst_other = 0.0;
  for (std::size_t k = 0; k < 2000; ++k) {
    ASSERT_EQ(mine[k].seq, k);
    ASSERT_EQ(theirs[k].seq, k);
    ASSERT_EQ(theirs[k].t_ns, *t0_other + static_cast<std::int64_t>(k) * 1'000'000);
    const double t_s = 1e-3 * static_cast<double>(k);
    const estimator::Observation y = ModelY(options.sim, options.omega_rad_s, t_s);
    const estimator::Observation y_other = ModelY(other, options.omega_rad_s, t_s);
    for (int c = 0; c < 4; ++c) {
      worst = std::max(worst, std::abs(mine[k].y[c] - y(c)));
      worst_other = std::max(worst_other, std::abs(theirs[k].y[c] - y_other(c)));
    }
  }
  EXPECT_LE(worst, drivers::gyro_can::kSampleLsb / 2 + 1e-12);
  EXPECT_LE(worst_other, drivers::gyro_can::kSampleLsb / 2 + 1e-12);
  EXPECT_GT(t0, 0);
  // The socket filter already kept the other node's frames out: every frame the transport
  // delivered was this driver's.
  EXPECT_EQ(rig.host_endpoint->Statistics().frames_received,
            rig.device->Counters().frames_received);
  EXPECT_EQ(other_host->Statistics().frames_received, (*other_device)->Counters().frames_received);
  for (const hw::GyroCounters& c : {rig.device->Counters(), (*other_device)->Counters()}) {
    EXPECT_EQ(c.unexpected_frames, 0u);
    EXPECT_EQ(c.bad_frames, 0u);
    EXPECT_EQ(c.samples_lost, 0u);
    EXPECT_EQ(c.sequence_gaps, 0u);
  }
  rig.clock.RemoveParticipant(&other_node);
}

// physics = "carrier": the same protocol and frames carry the carrier-level chain's samples, bit
// for bit what CarrierSimulation gives for the same wave, Ω, seed and run; Status reports the
// mode's frequency at the housing temperature, f(T) = f0·(1 + α·(T − T0)).
TEST(GyroCanDeviceTest, CarrierPhysicsStreamsTheChainsSamples) {
  GyroRigOptions options;
  options.sim.physics = drivers::sim::GyroPhysics::kCarrier;
  options.sim.seed = 77;
  drivers::sim::CarrierOptions& carrier = options.sim.carrier;
  carrier.resonator.frequency_split_hz = 0.01;
  carrier.resonator.frequency_axis_rad = 0.3;
  carrier.pickoff.errors = {0.98, 0.002, 0.001, 0.002};
  carrier.pickoff.white_noise_std = 1e-3;
  carrier.frequency_temperature_coefficient_per_c = 5e-5;
  carrier.reference_temperature_c = 20.0;
  options.sim.temperature_c = 30.0;
  GyroRig rig(options);
  rig.StartRun(1000, kWave);
  const std::vector<GyroSample> samples = ReadN(*rig.device, 2000);
  ASSERT_EQ(samples.size(), 2000u);

  drivers::sim::CarrierSimulation chain(carrier);
  drivers::sim::CarrierRelease release;
  release.orbit = rig.node->commanded_orbit();
  release.omega_rad_s = options.omega_rad_s;
  release.output_rate_hz = 1000.0;
  release.seed = 77;  // seed + run 0
  release.temperature_c = 30.0;
  chain.Release(release);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const estimator::Observation y = chain.Next(options.omega_rad_s);
    for (int c = 0; c < 4; ++c) ASSERT_EQ(samples[k].y[c], y(c)) << k << " " << c;
  }
  ASSERT_TRUE(rig.device->Stop().has_value());
  EXPECT_NEAR(rig.device->LastStatus().resonant_frequency_hz, 5000.0 * (1 + 5e-5 * 10.0), 1e-3);
}

TEST(GyroCanDeviceTest, CanFdPacksFiveSamplesPerFrame) {
  GyroRigOptions options;
  options.sim = NoiseFreeModel();
  options.fd_bus = true;
  options.device.prefer_fd = true;
  GyroRig rig(options);
  const std::int64_t t0 = rig.StartRun(5000, kWave);
  EXPECT_EQ(rig.device->frame_format(), drivers::gyro_can::FrameFormat::kFd);
  const std::vector<GyroSample> samples = ReadN(*rig.device, 10'000);
  ASSERT_EQ(samples.size(), 10'000u);
  for (std::size_t k = 0; k < samples.size(); k += 997) {
    EXPECT_EQ(samples[k].seq, k);
    EXPECT_EQ(samples[k].t_ns, t0 + static_cast<std::int64_t>(k) * 200'000);
    const estimator::Observation y =
        ModelY(options.sim, options.omega_rad_s, 2e-4 * static_cast<double>(k));
    for (int c = 0; c < 4; ++c)
      EXPECT_NEAR(samples[k].y[c], y(c), drivers::gyro_can::kSampleLsb / 2 + 1e-12);
  }
  EXPECT_EQ(rig.device->Counters().sequence_gaps, 0u);
  // 10 000 samples in 2 000 frames (+ commands and status).
  EXPECT_LT(rig.device->Counters().frames_received, 2'100u);
}

TEST(GyroCanDeviceTest, StateMachineRefusesOutOfOrderCommands) {
  GyroRig rig(GyroRigOptions{});
  EXPECT_EQ(rig.device->Excite(kWave).error().code, GyroErrorCode::kInvalidState);
  EXPECT_EQ(rig.device->Release().error().code, GyroErrorCode::kInvalidState);
  EXPECT_EQ(rig.device->WaitReady(1'000'000).error().code, GyroErrorCode::kInvalidState);
  EXPECT_EQ(rig.device->Configure({5000}).error().code, GyroErrorCode::kInvalidArgument);
  ASSERT_TRUE(rig.device->Configure({1000}).has_value());
  EXPECT_EQ(rig.device->Release().error().code, GyroErrorCode::kInvalidState);
  EXPECT_EQ(rig.device->Excite({1.0, 1.5, 0.0}).error().code, GyroErrorCode::kInvalidArgument);
  ASSERT_TRUE(rig.device->Excite(kWave).has_value());
  EXPECT_EQ(rig.device->State(), GyroMode::kExciting);
  // Release before the wave is there: the host refuses (state Exciting), nothing is sent.
  EXPECT_EQ(rig.device->Release().error().code, GyroErrorCode::kInvalidState);
  hw::GyroSample sample;
  EXPECT_EQ(rig.device->ReadSamples({&sample, 1}, 0).status, GyroReadStatus::kNotRunning);
  EXPECT_EQ(rig.device->Counters().nacks, 0u);
}

TEST(GyroCanDeviceTest, LostFramesAreCountedAsSequenceGaps) {
  GyroRig rig(GyroRigOptions{});
  rig.StartRun(1000, kWave);
  const std::vector<GyroSample> before = ReadN(*rig.device, 100);
  ASSERT_EQ(before.size(), 100u);
  // Three frames: A(k), B(k), A(k+1) → samples k and k+1 lost, one break in the sequence.
  rig.node->faults().drop_sample_frames = 3;
  std::vector<GyroSample> after = ReadN(*rig.device, 100);
  ASSERT_EQ(after.size(), 100u);
  EXPECT_EQ(rig.device->Counters().sequence_gaps, 1u);
  EXPECT_EQ(rig.device->Counters().samples_lost, 2u);
  EXPECT_EQ(after.back().seq - before.back().seq, 102u);
  // Frames lost on the bus (not by the node) are found the same way.
  rig.bus->DropNext(1);
  after = ReadN(*rig.device, 50);
  ASSERT_EQ(after.size(), 50u);
  EXPECT_EQ(rig.device->Counters().sequence_gaps, 2u);
  EXPECT_EQ(rig.device->Counters().samples_lost, 3u);
  // A burst longer than the 8-bit counter's wrap (300 samples = 600 frames; a wrap is 256) cannot
  // be numbered: from the counter and the receive stamp, a whole wrap lost and a sender that fell
  // behind look the same, and a guess shifts the rest of the run by a wrap and pairs the halves of
  // different samples (issue 25 row 15; README "Sequence counter"). The rest of the run is refused
  // and counted lost, never delivered with a guessed number.
  rig.node->faults().drop_sample_frames = 600;
  after = ReadN(*rig.device, 50, nullptr, 1'000'000'000);
  EXPECT_TRUE(after.empty()) << after.size() << " samples delivered with a guessed number";
  EXPECT_EQ(rig.device->Counters().sequence_gaps, 3u);
  EXPECT_GE(rig.device->Counters().samples_lost, 3u + 300u);
}

TEST(GyroCanDeviceTest, CorruptFramesAreCountedAsBadFrames) {
  GyroRig rig(GyroRigOptions{});
  rig.StartRun(1000, kWave);
  ASSERT_EQ(ReadN(*rig.device, 10).size(), 10u);
  rig.node->faults().corrupt_sample_frames = 1;
  ReadN(*rig.device, 10);
  EXPECT_EQ(rig.device->Counters().bad_frames, 1u);
  EXPECT_EQ(rig.device->Counters().samples_lost, 1u);
  rig.bus->CorruptNext(4);  // one flipped bit each, on the bus
  ReadN(*rig.device, 20);
  EXPECT_EQ(rig.device->Counters().bad_frames, 5u);
  EXPECT_GE(rig.device->Counters().samples_lost, 3u);
}

TEST(GyroCanDeviceTest, StallIsATimeout) {
  GyroRigOptions options;
  options.sim.faults.stall_after_samples = 500;
  GyroRig rig(options);
  rig.StartRun(1000, kWave);
  GyroReadStatus status = GyroReadStatus::kOk;
  const std::vector<GyroSample> samples = ReadN(*rig.device, 1000, &status);
  EXPECT_EQ(samples.size(), 500u);
  EXPECT_EQ(status, GyroReadStatus::kTimeout);
  EXPECT_EQ(rig.device->Counters().timeouts, 1u);
  EXPECT_EQ(rig.device->State(), GyroMode::kFreeRun);  // the host decides what a stall means
  EXPECT_TRUE(rig.device->Stop().has_value());         // the node still answers commands
}

TEST(GyroCanDeviceTest, NoReplyIsBoundedRetriesThenAnError) {
  GyroRigOptions options;
  options.sim.faults.no_reply = true;
  GyroRig rig(options);
  const std::int64_t start = rig.clock.NowNs();
  const auto result = rig.device->Configure({1000});
  ASSERT_FALSE(result.has_value());
  EXPECT_EQ(result.error().code, GyroErrorCode::kTimeout);
  const std::int64_t elapsed = rig.clock.NowNs() - start;
  EXPECT_GE(elapsed, 3 * 50'000'000);
  EXPECT_LT(elapsed, 3 * 50'000'000 + 1'000'000);
  EXPECT_EQ(rig.device->Counters().timeouts, 3u);
  EXPECT_EQ(rig.device->Counters().command_retries, 2u);
  EXPECT_EQ(rig.device->State(), GyroMode::kIdle);
}

TEST(GyroCanDeviceTest, RetriesRecoverLostCommandsAndAcks) {
  GyroRigOptions options;
  options.sim.faults.ignore_commands = 2;
  GyroRig rig(options);
  ASSERT_TRUE(rig.device->Configure({1000}).has_value());
  EXPECT_EQ(rig.device->Counters().command_retries, 2u);
  ASSERT_TRUE(rig.device->Excite(kWave).has_value());
  ASSERT_TRUE(rig.device->WaitReady(2'000'000'000).has_value());
  // Lose the Release command itself on the bus: the retry releases, t0 is still sample 0's time.
  rig.bus->DropNext(1);
  const auto t0 = rig.device->Release();
  ASSERT_TRUE(t0.has_value());
  EXPECT_EQ(rig.device->Counters().command_retries, 3u);
  const std::vector<GyroSample> samples = ReadN(*rig.device, 10);
  ASSERT_EQ(samples.size(), 10u);
  EXPECT_EQ(samples[0].seq, 0u);
  EXPECT_EQ(rig.node->Statistics().runs, 1u);
}

TEST(GyroCanDeviceTest, BusOffIsAnErrorState) {
  GyroRigOptions options;
  options.sim.faults.bus_off_after_samples = 100;
  GyroRig rig(options);
  rig.StartRun(1000, kWave);
  GyroReadStatus status = GyroReadStatus::kOk;
  ReadN(*rig.device, 1000, &status);
  EXPECT_EQ(status, GyroReadStatus::kBusOff);
  EXPECT_EQ(rig.device->State(), GyroMode::kFaulted);
  EXPECT_GE(rig.device->Counters().bus_errors, 1u);
  EXPECT_EQ(rig.device->Stop().error().code, GyroErrorCode::kBusOff);
  // The bus recovers: Stop leaves Faulted, a new run can be configured.
  rig.bus->SetBusOff(false);
  ASSERT_TRUE(rig.device->Stop().has_value());
  EXPECT_TRUE(rig.device->Configure({1000}).has_value());
}

TEST(GyroCanDeviceTest, ReportedFaultStopsWaitReady) {
  GyroRig rig(GyroRigOptions{});
  ASSERT_TRUE(rig.device->Configure({1000}).has_value());
  ASSERT_TRUE(rig.device->Excite(kWave).has_value());
  rig.node->faults().fault_bits = hw::gyro_fault::kPllUnlock;
  const auto ready = rig.device->WaitReady(2'000'000'000);
  ASSERT_FALSE(ready.has_value());
  EXPECT_EQ(ready.error().code, GyroErrorCode::kFaulted);
  EXPECT_EQ(rig.device->State(), GyroMode::kFaulted);
  EXPECT_EQ(rig.device->LastStatus().fault_bits, hw::gyro_fault::kPllUnlock);
  EXPECT_EQ(rig.device->Excite(kWave).error().code, GyroErrorCode::kInvalidState);
  ASSERT_TRUE(rig.device->Stop().has_value());
  EXPECT_TRUE(rig.device->Configure({1000}).has_value());
}

TEST(GyroCanDeviceTest, WaitReadyTimesOutWhileTheWaveSettles) {
  GyroRigOptions options;
  options.sim.excite_time_s = 5.0;
  GyroRig rig(options);
  ASSERT_TRUE(rig.device->Configure({1000}).has_value());
  ASSERT_TRUE(rig.device->Excite(kWave).has_value());
  EXPECT_EQ(rig.device->WaitReady(500'000'000).error().code, GyroErrorCode::kTimeout);
  EXPECT_TRUE(rig.device->WaitReady(5'000'000'000).has_value());
}

}  // namespace
}  // namespace hrgbench::testing
