// The in-process simulated station through the hw interfaces only: a free run by hand faster than
// real time, three runs estimated against the simulator's truth, the bench's thread layout over
// six 100 s runs, the raw-frame tap, and the real-time and paced modes.
//
// Synthetic data provenance: GyroSimNode (drivers/sim) with the truth below, σ = 1e-4, seed 7
// (run r uses NormalGenerator(7 + r)); table physics seed 1.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <thread>

#include "gyro_can/gyro_codec.hpp"
#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "sim/simulated_station.hpp"
#include "station_driver.hpp"

namespace hrgbench::testing {
namespace {

using drivers::sim_station::SimulatedStation;
using drivers::sim_station::SimulatedStationOptions;

const hw::WaveState kWave{1.0, -0.4, std::numbers::pi / 7};
constexpr double kEarthRate = 7.2921150e-5 * 0.7071;  // axis up at 45° N

double WallSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

SimulatedStationOptions Options(double sigma = 0.0) {
  SimulatedStationOptions o;
  o.units[0].gyro.delta << -0.001, 0.3, 2e-4, -1e-4, 3e-4, -2e-4;
  o.units[0].gyro.xi << 0.01, -0.004, 0.003, 0.002;
  o.units[0].gyro.sigma = sigma;
  o.units[0].gyro.seed = 7;
  o.earth_rate_rad_s = kEarthRate;
  return o;
}

std::unique_ptr<SimulatedStation> MakeStation(const SimulatedStationOptions& options) {
  auto station = SimulatedStation::Create(options);
  EXPECT_TRUE(station.has_value()) << (station ? "" : station.error());
  if (!station) return nullptr;
  auto connected = (*station)->table().Connect();
  EXPECT_TRUE(connected.has_value()) << connected.error().ToString();
  return std::move(*station);
}

void ExpectCompleteAndInOrder(const FreeRun& run, std::size_t n, std::int64_t period_ns) {
  ASSERT_EQ(run.samples.size(), n);
  for (std::size_t k = 0; k < n; ++k) {
    ASSERT_EQ(run.samples[k].seq, k);
    ASSERT_EQ(run.samples[k].t_ns, run.t0_ns + static_cast<std::int64_t>(k) * period_ns);
  }
}

TEST(SimStationTest, FreeRunFasterThanRealTime) {
  auto station = MakeStation(Options());
  ASSERT_NE(station, nullptr);
  EXPECT_TRUE(station->faster_than_real_time());
  const auto wall = std::chrono::steady_clock::now();
  auto run = DoFreeRun(station->table(), station->gyro(), 0.5, kWave, 10'000);
  ASSERT_TRUE(run.has_value()) << run.error();
  station->table().SafeStop();
  const double wall_s = WallSince(wall);
  ExpectCompleteAndInOrder(*run, 10'000, 1'000'000);
  EXPECT_NEAR(run->stable_status.measured_rate_rad_s, 0.5, 1e-3);
  const hw::GyroCounters c = station->gyro().Counters();
  EXPECT_EQ(c.sequence_gaps, 0u);
  EXPECT_EQ(c.bad_frames, 0u);
  EXPECT_EQ(c.kernel_drops, 0u);
  EXPECT_EQ(station->gyro().State(), hw::GyroMode::kStopped);
  EXPECT_EQ(station->in_process_table().target_rate_rad_s(), 0.0);
  // Simulated: ramp + settle + dwell (~1.3 s) + excite (0.2 s) + 10 s of samples.
  const double sim_s = static_cast<double>(station->clock().NowNs()) * 1e-9;
  EXPECT_GT(sim_s, 11.0);
  EXPECT_LT(sim_s, 13.0);
  std::printf("[ info ] %.1f s simulated (10 s at 1 kHz) in %.3f s wall\n", sim_s, wall_s);
}

TEST(SimStationTest, RawFrameTapSeesBothDirectionsInBusOrder) {
  auto station = MakeStation(Options());
  ASSERT_NE(station, nullptr);
  auto run = DoFreeRun(station->table(), station->gyro(), 0.2, kWave, 100);
  ASSERT_TRUE(run.has_value()) << run.error();
  hw::CanFrame frame;
  hw::ReceiveInfo info;
  std::int64_t last_ns = 0;
  std::size_t commands = 0, acks = 0, samples = 0, total = 0;
  while (station->monitor().Receive(&frame, 0, &info) == hw::CanStatus::kOk) {
    ++total;
    EXPECT_GE(info.timestamp_ns, last_ns);
    EXPECT_EQ(info.dropped_frames, 0u);
    last_ns = info.timestamp_ns;
    if (drivers::gyro_can::IsCommandId(frame.id)) ++commands;
    if (frame.id == drivers::gyro_can::can_id::kAck) ++acks;
    if (frame.id == drivers::gyro_can::can_id::kSampleA ||
        frame.id == drivers::gyro_can::can_id::kSampleB)
      ++samples;
  }
  EXPECT_GE(commands, 4u);  // Configure, Excite, Release, Stop (+ status requests)
  EXPECT_EQ(acks, commands);
  EXPECT_GE(samples, 200u);  // two classic frames per sample; the stream may run on to Stop
  EXPECT_GT(total, commands + acks + samples);  // + status frames
}

TEST(SimStationTest, ThreeRunsEstimateTheTruthWithinFiveSigma) {
  auto station = MakeStation(Options(1e-4));
  ASSERT_NE(station, nullptr);
  const drivers::sim_station::SimulatedTruth truth = station->truth();
  std::vector<estimator::RunData> runs;
  const auto wall = std::chrono::steady_clock::now();
  int id = 1;
  for (double omega : {0.5, -0.3, 1.0}) {
    auto run = DoFreeRun(station->table(), station->gyro(), omega, kWave, 10'000);
    ASSERT_TRUE(run.has_value()) << run.error();
    ExpectCompleteAndInOrder(*run, 10'000, 1'000'000);
    estimator::RunData data;
    data.id = id++;
    // Ω for the estimator: the table rate (settled on the command) + the Earth-rate component.
    data.omega_rad_s = omega + truth.earth_rate_rad_s;
    // reserve + push_back: GCC 12 reports a false null dereference inside vector::resize here.
    data.t_s.reserve(run->samples.size());
    data.y.resize(4, static_cast<Eigen::Index>(run->samples.size()));
    for (std::size_t k = 0; k < run->samples.size(); ++k) {
      data.t_s.push_back(static_cast<double>(run->samples[k].t_ns - run->t0_ns) * 1e-9);
      for (int c = 0; c < 4; ++c) data.y(c, static_cast<Eigen::Index>(k)) = run->samples[k].y[c];
    }
    runs.push_back(std::move(data));
  }
  station->table().SafeStop();
  const double capture_wall_s = WallSince(wall);
  const estimator::EstimateSummary summary = estimator::EstimateMaximumLikelihood(runs);
  ASSERT_TRUE(summary.IsUsable()) << summary.Report();
  int compared = 0;
  for (int i = 0; i < 6; ++i) {
    if (!summary.delta_estimated[i]) continue;
    ++compared;
    EXPECT_LE(std::abs(summary.delta(i) - truth.delta(i)), 5 * summary.delta_std(i))
        << "delta" << i + 1 << "\n"
        << summary.Report();
  }
  for (int i = 0; i < 4; ++i) {
    if (!summary.xi_estimated[i]) continue;
    ++compared;
    EXPECT_LE(std::abs(summary.xi(i) - truth.xi(i)), 5 * summary.xi_std(i)) << "xi" << i + 1 << "\n"
                                                                            << summary.Report();
  }
  EXPECT_GE(compared, 6);
  // σ̂ ≈ σ: the wire's quantisation (LSB 2^-22) adds LSB²/12, negligible.
  EXPECT_NEAR(summary.noise_sigma, truth.sigma, 0.1 * truth.sigma);
  std::printf("[ info ] 3 runs x 10 s captured in %.3f s wall; %d parameters within 5 std\n",
              capture_wall_s, compared);
}

// The bench's layout: a sequencer thread owning the table (keeping its heartbeat while the run
// captures), a capture thread owning the gyro, a recorder thread draining the raw-frame tap; all
// of them wait on the station's clock. Six runs of 100 s at 1 kHz.
TEST(SimStationTest, BenchThreadsCaptureSixHundredSecondRunsInSeconds) {
  auto station = MakeStation(Options(1e-4));
  ASSERT_NE(station, nullptr);
  hw::Clock& clock = station->clock();
  constexpr int kRuns = 6;
  constexpr std::size_t kSamples = 100'000;
  std::atomic<int> requested{0}, captured{0};
  std::atomic<std::uint64_t> tap_frames{0}, tap_drops{0};
  std::vector<FreeRun> results(kRuns);
  std::string capture_error;

  // This thread owns the table and feeds its watchdog: it holds simulated time back from now
  // on, before the other threads start waiting (unattached, time ran on while it was starting
  // them, and on a loaded machine the watchdog expired before the first heartbeat).
  station->virtual_clock()->AttachCurrentThread();
  const auto wall = std::chrono::steady_clock::now();
  // jthreads: stopped and joined on every way out of the test, a failed ASSERT included.
  std::jthread capture([&](const std::stop_token& stop_token) {
    station->virtual_clock()->AttachCurrentThread();
    hw::GyroElectronics& gyro = station->gyro();
    for (int k = 1; k <= kRuns; ++k) {
      while (requested.load() < k) {
        if (stop_token.stop_requested()) return;
        clock.SleepForNs(10'000'000);
      }
      FreeRun& run = results[k - 1];
      if (auto ok = gyro.Configure({1000}); !ok) capture_error = ok.error().ToString();
      if (auto ok = gyro.Excite(kWave); !ok) capture_error = ok.error().ToString();
      if (auto ok = gyro.WaitReady(2'000'000'000); !ok) capture_error = ok.error().ToString();
      auto t0 = gyro.Release();
      if (!t0) capture_error = t0.error().ToString();
      run.t0_ns = t0.value_or(0);
      ReadSamples(gyro, kSamples, &run);
      if (auto ok = gyro.Stop(); !ok) capture_error = ok.error().ToString();
      captured.store(k);
    }
  });
  std::jthread recorder([&](const std::stop_token& stop_token) {
    station->virtual_clock()->AttachCurrentThread();
    hw::CanFrame frame;
    hw::ReceiveInfo info;
    while (!stop_token.stop_requested()) {
      if (station->monitor().Receive(&frame, 100'000'000, &info) == hw::CanStatus::kOk) {
        tap_frames.fetch_add(1);
        tap_drops.fetch_add(info.dropped_frames);
      }
    }
  });
  hw::RateTable& table = station->table();
  for (int k = 1; k <= kRuns; ++k) {
    const double omega = 0.25 * k * (k % 2 == 0 ? -1.0 : 1.0);
    ASSERT_TRUE(table.SetRate(omega).has_value());
    auto stable = table.WaitUntilStable(TestCriteria());
    ASSERT_TRUE(stable.has_value()) << stable.error().ToString();
    results[k - 1].omega_rad_s = omega;
    requested.store(k);
    while (captured.load() < k) {  // the run captures; keep the table's watchdog fed
      ASSERT_TRUE(table.Heartbeat().has_value());
      const auto status = table.ReadStatus();
      ASSERT_TRUE(status.has_value());
      ASSERT_FALSE(status->fault);
      clock.SleepForNs(100'000'000);
    }
  }
  table.SafeStop();
  station->virtual_clock()->DetachCurrentThread();  // joining is not waiting on the clock
  capture.join();
  recorder.request_stop();
  recorder.join();
  const double wall_s = WallSince(wall);
  ASSERT_TRUE(capture_error.empty()) << capture_error;
  for (const FreeRun& run : results) ExpectCompleteAndInOrder(run, kSamples, 1'000'000);
  const hw::GyroCounters c = station->gyro().Counters();
  // The stream runs on until each Stop is acknowledged: up to the clock's 20 ms output lookahead
  // (20 samples) more per run are decoded and discarded by Stop.
  EXPECT_GE(c.samples_decoded, kRuns * kSamples);
  EXPECT_LE(c.samples_decoded, kRuns * (kSamples + 25));
  EXPECT_EQ(c.sequence_gaps, 0u);
  EXPECT_EQ(c.kernel_drops, 0u);
  EXPECT_EQ(c.buffer_overruns, 0u);
  EXPECT_GE(tap_frames.load(), 2 * kRuns * kSamples);
  EXPECT_EQ(tap_drops.load(), 0u);
  const drivers::sim_station::VirtualTimeClockStatistics s = station->virtual_clock()->Statistics();
  const double sim_s = static_cast<double>(clock.NowNs()) * 1e-9;
  EXPECT_GT(sim_s, kRuns * 100.0);
  EXPECT_EQ(s.attached_threads, 0u);
  std::printf(
      "[ info ] %d x 100 s at 1 kHz (%.0f s simulated, %llu tap frames) in %.2f s wall; "
      "%llu advances, %llu parks\n",
      kRuns, sim_s, static_cast<unsigned long long>(tap_frames.load()), wall_s,
      static_cast<unsigned long long>(s.advances), static_cast<unsigned long long>(s.parks));
}

TEST(SimStationTest, RealTimeRunTakesItsLengthInWallTime) {
  SimulatedStationOptions options = Options();
  options.faster_than_real_time = false;
  options.time_scale = 1.0;
  auto station = MakeStation(options);
  ASSERT_NE(station, nullptr);
  EXPECT_FALSE(station->faster_than_real_time());
  hw::RateTable& table = station->table();
  hw::GyroElectronics& gyro = station->gyro();
  ASSERT_TRUE(table.SetRate(0.2).has_value());
  ASSERT_TRUE(table.WaitUntilStable(TestCriteria()).has_value());
  ASSERT_TRUE(gyro.Configure({1000}).has_value());
  ASSERT_TRUE(gyro.Excite(kWave).has_value());
  ASSERT_TRUE(gyro.WaitReady(2'000'000'000).has_value());
  const auto wall = std::chrono::steady_clock::now();
  const std::int64_t sim_start = station->clock().NowNs();
  auto t0 = gyro.Release();
  ASSERT_TRUE(t0.has_value()) << t0.error().ToString();
  FreeRun run;
  run.t0_ns = *t0;
  ReadSamples(gyro, 500, &run);
  // Read in this order, the simulated interval lies inside the wall one.
  const double sim_s = static_cast<double>(station->clock().NowNs() - sim_start) * 1e-9;
  const double wall_s = WallSince(wall);
  ASSERT_TRUE(gyro.Stop().has_value());
  table.SafeStop();
  ExpectCompleteAndInOrder(run, 500, 1'000'000);
  // The last sample is due 0.499 s after the release, and the station's clock is the wall clock
  // here: the run takes its length (a loaded machine can only make it longer).
  EXPECT_GE(sim_s, 0.45);
  EXPECT_LE(sim_s, wall_s + 1e-3);
  std::printf("[ info ] real time: 0.5 s run in %.3f s wall\n", wall_s);
}

TEST(SimStationTest, PacedModeRunsAtItsTimeScale) {
  SimulatedStationOptions options = Options();
  options.faster_than_real_time = false;
  options.time_scale = 20.0;
  auto station = MakeStation(options);
  ASSERT_NE(station, nullptr);
  EXPECT_TRUE(station->faster_than_real_time());  // virtual time, paced
  const auto wall = std::chrono::steady_clock::now();
  auto run = DoFreeRun(station->table(), station->gyro(), 0.3, kWave, 2'000);
  ASSERT_TRUE(run.has_value()) << run.error();
  const double wall_s = WallSince(wall);
  const double sim_s = static_cast<double>(station->clock().NowNs()) * 1e-9;
  ExpectCompleteAndInOrder(*run, 2'000, 1'000'000);
  // Never faster than its scale (it failed here: pacing counted from the clock's construction, so
  // a station that took a while to set up ran ahead to "catch up"). Speed is not judged here.
  EXPECT_GE(wall_s, 0.9 * sim_s / 20.0);
  std::printf("[ info ] paced x20: %.2f s simulated in %.3f s wall\n", sim_s, wall_s);
}

// Units at 1 kHz on one classic 1 Mbit/s bus (nodes 0, 1, ...), released together, read in turn.
// Each unit sends 2010 frames/s (two per sample, status at 10 Hz; the slow physics reports no
// reference phase) of 111 bits plus their stuff bits: ~23 % of the bus each. Four units fit (~92 %,
// nothing lost); five (~115 %) do not: the bus falls behind, the electronics' 32-frame transmit
// queues fill and frames are lost at their source, which each driver sees as gaps in the sample
// numbers and the electronics report as sample overrun (fault bit 4).
struct SharedBusRun {
  std::vector<hw::GyroCounters> counters;
  std::vector<std::uint8_t> fault_bits;
  double bus_load = 0.0;  // busy time / elapsed, from release to the end
};

SharedBusRun UnitsOnOneBus(std::size_t units, double seconds) {
  SimulatedStationOptions options = Options(1e-4);
  options.units.resize(units, options.units[0]);
  for (std::size_t i = 0; i < units; ++i) {
    options.units[i].bus = "shared";
    options.units[i].gyro.node = static_cast<drivers::gyro_can::NodeId>(i);
    options.units[i].gyro.seed = 7 + i;
  }
  SharedBusRun run;
  auto station = MakeStation(options);
  if (station == nullptr) return run;
  for (std::size_t i = 0; i < units; ++i) {
    EXPECT_TRUE(station->gyro(i).Configure({1000}).has_value());
    EXPECT_TRUE(station->gyro(i).Excite(kWave).has_value());
  }
  for (std::size_t i = 0; i < units; ++i)
    EXPECT_TRUE(station->gyro(i).WaitReady(2'000'000'000).has_value());
  for (std::size_t i = 0; i < units; ++i) EXPECT_TRUE(station->gyro(i).Release().has_value());
  const std::int64_t start_ns = station->clock().NowNs();
  const std::int64_t busy_at_start = station->bus(0).Statistics().busy_ns;
  const std::int64_t end_ns = start_ns + static_cast<std::int64_t>(seconds * 1e9);
  hw::GyroSample chunk[64];
  while (station->clock().NowNs() < end_ns) {
    for (std::size_t i = 0; i < units; ++i) (void)station->gyro(i).ReadSamples(chunk, 1'000'000);
  }
  run.bus_load = static_cast<double>(station->bus(0).Statistics().busy_ns - busy_at_start) /
                 static_cast<double>(station->clock().NowNs() - start_ns);
  for (std::size_t i = 0; i < units; ++i) {
    EXPECT_EQ(&station->bus(i), &station->bus(0));  // one bus
    run.counters.push_back(station->gyro(i).Counters());
    // The last periodic status heard (a request could itself be lost at a full queue).
    run.fault_bits.push_back(station->gyro(i).LastStatus().fault_bits);
  }
  return run;
}

TEST(SimStationTest, UnitsThatOverloadTheirSharedBusLoseSamplesAtTheSource) {
  const SharedBusRun four = UnitsOnOneBus(4, 5.0);
  ASSERT_EQ(four.counters.size(), 4u);
  // 4 × 2010 frames/s × (111 … 135) µs: between 89 % and 109 %; the real stuff bits make ~92 %.
  EXPECT_GT(four.bus_load, 4 * 2010 * 111e-6);
  EXPECT_LT(four.bus_load, 1.0);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_GT(four.counters[i].samples_decoded, 4900u);
    EXPECT_EQ(four.counters[i].sequence_gaps, 0u);
    EXPECT_EQ(four.counters[i].unexpected_frames, 0u);
    EXPECT_EQ(four.fault_bits[i] & hw::gyro_fault::kSampleOverrun, 0);
  }
  const SharedBusRun five = UnitsOnOneBus(5, 5.0);
  ASSERT_EQ(five.counters.size(), 5u);
  EXPECT_GT(five.bus_load, 0.99);  // saturated
  for (std::size_t i = 0; i < 5; ++i) {
    SCOPED_TRACE(i);
    EXPECT_GT(five.counters[i].sequence_gaps, 0u);
    EXPECT_GT(five.counters[i].samples_lost, 0u);
    EXPECT_NE(five.fault_bits[i] & hw::gyro_fault::kSampleOverrun, 0);
  }
  std::printf(
      "[ info ] one 1 Mbit/s bus at 1 kHz: 4 units %.1f %% busy, 0 lost; 5 units %.1f %%, "
      "unit 1 lost %llu of %llu samples\n",
      100 * four.bus_load, 100 * five.bus_load,
      static_cast<unsigned long long>(five.counters[0].samples_lost),
      static_cast<unsigned long long>(five.counters[0].samples_lost +
                                      five.counters[0].samples_decoded));
}

TEST(SimStationTest, InvalidOptionsNameTheField) {
  SimulatedStationOptions options;
  options.faster_than_real_time = false;
  options.time_scale = 0.0;
  auto station = SimulatedStation::Create(options);
  ASSERT_FALSE(station.has_value());
  EXPECT_NE(station.error().find("time_scale"), std::string::npos);
  options = {};
  options.units[0].gyro.sigma = -1.0;
  station = SimulatedStation::Create(options);
  ASSERT_FALSE(station.has_value());
  EXPECT_NE(station.error().find("units[0].gyro: sigma"), std::string::npos);
  options = {};
  options.units.clear();
  station = SimulatedStation::Create(options);
  ASSERT_FALSE(station.has_value());
  EXPECT_NE(station.error().find("units: between 1 and 16 units, got 0"), std::string::npos);
}

}  // namespace
}  // namespace hrgbench::testing
