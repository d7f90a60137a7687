// The estimate's memory per sample of the session (docs/estimator/methods.md "Memory"), with the
// runs kept in memory (the default) and with none kept (--memory-mib 0, the run spool):
// hrg-estimate on two hrg-sim sessions of runs of the same length (10 000 samples each), 6 runs and
// 60 runs; the difference of the two processes' peak RSS (the kernel's ru_maxrss of each child, a
// size, not a time) divided by the 540 000 samples the second has more is what one more sample of
// the session costs. main before this bound: 113 bytes per sample (the reader's copy, the runs'
// copy and every run's residuals, 40 + 40 + 32); now the runs' t_s and y once, 40, plus the runs'
// small per-run state.
//
// Provenance: bench_configs/sim-ratetable.toml's station (1 kHz, σ = 1e-4, seed 12345, all four ξ),
// its runs cycled over Ω = ±0.1, ±0.3, ±1 rad/s and θ = kπ/12, 10 s each.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "record_test_dir.hpp"

namespace {

namespace fs = std::filesystem;

// The estimate may keep this much per sample of the session (t_s and y as doubles are 40).
constexpr double kMaxBytesPerSessionSample = 60.0;

std::string ReadAll(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// sim-ratetable.toml with `runs` runs of 10 s.
std::string Spec(int runs) {
  std::string head = ReadAll(fs::path(HRGBENCH_SOURCE_DIR) / "bench_configs/sim-ratetable.toml");
  head = head.substr(0, head.find("[[runs]]"));
  head = std::regex_replace(head, std::regex("duration_s = [0-9.]+"), "duration_s = 10.0");
  const double omegas[] = {0.1, -0.1, 0.3, -0.3, 1.0, -1.0};
  std::ostringstream spec;
  spec.precision(17);
  spec << head;
  for (int k = 0; k < runs; ++k)
    spec << "[[runs]]\nomega_rad_s = " << omegas[k % 6]
         << "\nb = 0.1\ntheta_rad = " << std::numbers::pi * (k % 12) / 12 << "\n\n";
  return spec.str();
}

// Runs `argv` with stdout and stderr to /dev/null; its exit code and peak RSS in bytes.
struct Child {
  int exit_code = -1;
  double peak_rss_bytes = 0.0;
};
Child RunChild(std::vector<std::string> argv) {
  std::vector<char*> args;
  for (std::string& a : argv) args.push_back(a.data());
  args.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(null, 2);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  Child child;
  int status = 0;
  struct rusage usage {};
  if (pid < 0 || ::wait4(pid, &status, 0, &usage) != pid) return child;
  child.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  child.peak_rss_bytes = static_cast<double>(usage.ru_maxrss) * 1024.0;  // Linux: kB
  return child;
}

// hrg-estimate's peak RSS on the 6-run and the 60-run session (made once), with `extra` arguments.
class EstimateMemory : public ::testing::Test {
 protected:
  static constexpr int kRuns[2] = {6, 60};
  static constexpr double kExtraSamples = (kRuns[1] - kRuns[0]) * 10'000.0;

  static void SetUpTestSuite() {
    dir_ = new hrgbench::testing::ScratchDir("estimate_memory");
    for (int i = 0; i < 2; ++i) {
      const fs::path spec = dir_->path() / ("spec-" + std::to_string(kRuns[i]) + ".toml");
      std::ofstream(spec) << Spec(kRuns[i]);
      sessions_[i] = dir_->path() / ("session-" + std::to_string(kRuns[i]));
      made_ = RunChild({HRG_SIM, spec.string(), "-o", sessions_[i].string()}).exit_code == 0;
      if (!made_) return;
    }
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }

  // Bytes of peak RSS per sample the 60-run session has more.
  static double PerSample(const std::vector<std::string>& extra, double peak[2]) {
    for (int i = 0; i < 2; ++i) {
      std::vector<std::string> argv = {HRG_ESTIMATE, sessions_[i].string(), "--json"};
      argv.insert(argv.end(), extra.begin(), extra.end());
      const Child estimate = RunChild(argv);
      EXPECT_EQ(estimate.exit_code, 0) << sessions_[i];
      peak[i] = estimate.peak_rss_bytes;
    }
    return (peak[1] - peak[0]) / kExtraSamples;
  }

  static inline hrgbench::testing::ScratchDir* dir_ = nullptr;
  static inline fs::path sessions_[2];
  static inline bool made_ = false;
};

// The default budget keeps both sessions in memory: the samples once, 40 bytes each.
TEST_F(EstimateMemory, PerSampleOfTheSessionBounded) {
  ASSERT_TRUE(made_);
  double peak[2];
  const double per_sample = PerSample({}, peak);
  EXPECT_LT(per_sample, kMaxBytesPerSessionSample)
      << "peak RSS " << peak[0] / 1e6 << " MB (6 runs), " << peak[1] / 1e6 << " MB (60 runs)";
  EXPECT_GT(per_sample, 0.0);
}

// Nothing kept (--memory-mib 0): the runs are read back on each pass, and the peak is that of the
// runs in use, the same for 6 runs as for 60 of the same length; what grows is the per-run state
// (each run's nuisance, normal equations and diagnostics: kilobytes, about 0.1 to 1 byte per
// sample here), far below the 40 bytes a kept sample takes.
constexpr double kMaxBytesPerSessionSampleSpooled = 4.0;

TEST_F(EstimateMemory, NothingKeptThePeakIsThatOfTheRunsInUse) {
  ASSERT_TRUE(made_);
  double peak[2];
  const double per_sample = PerSample({"--memory-mib", "0"}, peak);
  EXPECT_LT(per_sample, kMaxBytesPerSessionSampleSpooled)
      << "peak RSS " << peak[0] / 1e6 << " MB (6 runs), " << peak[1] / 1e6 << " MB (60 runs)";
}

}  // namespace
