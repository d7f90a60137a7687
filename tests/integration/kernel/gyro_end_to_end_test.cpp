// End to end across processes over a real kernel's vcan0 (inside the QEMU guest): hrg-gyro-sim, the
// simulated electronics, runs as a child process; this process drives it with the production gyro
// driver (GyroCanDevice over SocketCanBus), captures three free runs at 200 Hz and estimates δ
// from them; the estimate must agree with the simulator's truth (gyro_sim_e2e.toml) within 5 of
// its own standard deviations, and no frame may be bad.
//
// What it does not ask of an emulated CPU (issue 25 row 15): that no frame is lost. Under load the
// guest is frozen for hundreds of milliseconds at a time; the simulator then sends what it owes in
// a burst and the kernel drops what the socket cannot hold. A lost frame costs its sample (the
// driver stamps every sample from its number, so the ones that arrive keep their times), and a
// run whose sample numbers the driver could no longer tell (a stall of most of a wrap of the 8-bit
// counter: 0.96 s at 200 Hz) ends without its samples and is captured again, at most kAttempts
// times per run. 200 Hz rather than 500: under stress-ng and parallel builds the guest's sender
// fell more than 384 ms behind (3/4 of a wrap at 500 Hz) in 4 attempts of one run in a row.
//
// Arguments after GoogleTest's: --sim PATH --config PATH. Without vcan0 (a host without AF_CAN) the
// test skips, unless HRGBENCH_REQUIRE_VCAN=1 (set by the VM harness).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "gyro_can/gyro_can_device.hpp"
#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/hw/clock.hpp"
#include "socketcan/socket_can_bus.hpp"

namespace {

std::string g_sim_path;
constexpr std::uint16_t kRateHz = 200;
std::string g_config_path;

class SimProcess {
 public:
  bool Start(const std::string& iface) {
    pid_ = ::fork();
    if (pid_ == 0) {
      ::execl(g_sim_path.c_str(), g_sim_path.c_str(), "--can", iface.c_str(), "--config",
              g_config_path.c_str(), static_cast<char*>(nullptr));
      std::_Exit(127);
    }
    return pid_ > 0;
  }
  ~SimProcess() {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      int status = 0;
      ::waitpid(pid_, &status, 0);
    }
  }

 private:
  pid_t pid_ = -1;
};

TEST(GyroEndToEnd, SimulatorAndDriverInSeparateProcessesOverVcan) {
  const char* iface_env = std::getenv("HRGBENCH_CAN_IFACE");
  const std::string iface = iface_env ? iface_env : "vcan0";
  const bool required = std::getenv("HRGBENCH_REQUIRE_VCAN") != nullptr;
  auto bus = hrgbench::drivers::socketcan::SocketCanBus::Open(iface, {});
  if (!bus) {
    if (required) FAIL() << bus.error();
    GTEST_SKIP() << bus.error();
  }
  ASSERT_FALSE(g_sim_path.empty()) << "pass --sim PATH --config PATH";
  SimProcess sim;
  ASSERT_TRUE(sim.Start(iface));

  hrgbench::hw::SteadyClock clock;
  hrgbench::drivers::gyro_can::GyroCanDeviceConfig config;
  config.clock = &clock;
  config.ack_timeout_ns = 200'000'000;  // the emulated CPU of the guest is slow
  auto device = hrgbench::drivers::gyro_can::GyroCanDevice::Create(**bus, config);
  ASSERT_TRUE(device) << device.error().ToString();
  // The child needs a moment to open its socket: the first command is retried until it answers.
  std::expected<void, hrgbench::hw::GyroError> configured;
  for (int attempt = 0; attempt < 50; ++attempt) {
    configured = (*device)->Configure({.sample_rate_hz = kRateHz});
    if (configured) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_TRUE(configured) << configured.error().ToString();

  const double omega_rad_s = 0.5;  // gyro_sim_e2e.toml
  const hrgbench::hw::WaveState waves[] = {{1.0, 0.1, 0.0}, {1.0, -0.2, 0.5}, {1.0, 0.3, 1.1}};
  std::vector<hrgbench::estimator::RunData> runs;
  std::vector<hrgbench::hw::GyroSample> buffer(256);
  constexpr int kAttempts = 6;
  int repeated = 0;
  for (const auto& wave : waves) {
    for (int attempt = 1;; ++attempt) {
      ASSERT_LE(attempt, kAttempts) << "no run captured whole in " << kAttempts << " attempts";
      if ((*device)->State() == hrgbench::hw::GyroMode::kStopped) {
        auto again =
            (*device)->Configure({.sample_rate_hz = kRateHz});  // Stop leaves it unconfigured
        ASSERT_TRUE(again) << again.error().ToString();
      }
      auto excited = (*device)->Excite(wave);
      ASSERT_TRUE(excited) << excited.error().ToString();
      auto ready = (*device)->WaitReady(5'000'000'000);
      ASSERT_TRUE(ready) << ready.error().ToString();
      auto release = (*device)->Release();
      ASSERT_TRUE(release) << release.error().ToString();
      hrgbench::estimator::RunData run;
      run.id = static_cast<int>(runs.size()) + 1;
      run.omega_rad_s = omega_rad_s;
      constexpr std::size_t kSamples = 3 * kRateHz;  // 3 s, fewer when frames are lost
      constexpr std::int64_t kRunNs = 3'000'000'000;
      run.y.resize(4, kSamples);
      bool whole = true;
      while (run.t_s.size() < kSamples) {
        const auto got = (*device)->ReadSamples(buffer, 1'000'000'000);
        if (got.status == hrgbench::hw::GyroReadStatus::kTimeout) {
          whole = false;  // the driver refuses samples it can no longer number
          break;
        }
        ASSERT_EQ(got.status, hrgbench::hw::GyroReadStatus::kOk);
        bool done = false;
        for (std::size_t i = 0; i < got.count && run.t_s.size() < kSamples; ++i) {
          const std::int64_t since_release_ns = buffer[i].t_ns - *release;
          if (since_release_ns >= kRunNs) {
            done = true;
            break;
          }
          const auto k = static_cast<Eigen::Index>(run.t_s.size());
          run.t_s.push_back(static_cast<double>(since_release_ns) * 1e-9);
          for (int c = 0; c < 4; ++c) run.y(c, k) = buffer[i].y[c];
        }
        if (done) break;
      }
      run.y.conservativeResize(4, static_cast<Eigen::Index>(run.t_s.size()));
      auto stopped = (*device)->Stop();
      ASSERT_TRUE(stopped) << stopped.error().ToString();
      if (whole) {
        runs.push_back(std::move(run));
        break;
      }
      ++repeated;
    }
  }
  const auto counters = (*device)->Counters();
  // Printed, not judged: what the emulated CPU cost (drops cost samples, never their times).
  std::printf(
      "frames %llu, kernel drops %llu, sequence gaps %llu, samples lost %llu, runs %d "
      "captured again\n",
      static_cast<unsigned long long>(counters.frames_received),
      static_cast<unsigned long long>(counters.kernel_drops),
      static_cast<unsigned long long>(counters.sequence_gaps),
      static_cast<unsigned long long>(counters.samples_lost), repeated);
  EXPECT_EQ(counters.bad_frames, 0u);
  for (const auto& run : runs) EXPECT_GE(run.t_s.size(), 2 * kRateHz) << "run " << run.id;

  hrgbench::estimator::MlOptions options;
  options.xi_estimated = hrgbench::estimator::kNoXi;
  const auto s = hrgbench::estimator::EstimateMaximumLikelihood(runs, options);
  ASSERT_TRUE(s.Converged()) << s.Report();
  const double truth[6] = {-0.05, 0.3, 2e-3, -1e-3, 3e-3, 1e-3};
  for (int j = 0; j < 6; ++j) {
    EXPECT_NEAR(s.delta[j], truth[j], 5 * s.delta_std[j]) << "delta" << j + 1 << "\n" << s.Report();
  }
  EXPECT_NEAR(s.noise_sigma, 1e-4, 0.2e-4);
  std::printf("%s", s.Report().c_str());
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::string(argv[i]) == "--sim") g_sim_path = argv[i + 1];
    if (std::string(argv[i]) == "--config") g_config_path = argv[i + 1];
  }
  return RUN_ALL_TESTS();
}
