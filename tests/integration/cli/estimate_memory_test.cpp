// The estimate's memory per sample of the session (docs/estimator/methods.md "Memory"):
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

TEST(EstimateMemory, PerSampleOfTheSessionBounded) {
  hrgbench::testing::ScratchDir dir("estimate_memory");
  double peak[2] = {0.0, 0.0};
  const int runs[2] = {6, 60};
  for (int i = 0; i < 2; ++i) {
    const fs::path spec = dir.path() / ("spec-" + std::to_string(runs[i]) + ".toml");
    std::ofstream(spec) << Spec(runs[i]);
    const fs::path session = dir.path() / ("session-" + std::to_string(runs[i]));
    ASSERT_EQ(RunChild({HRG_SIM, spec.string(), "-o", session.string()}).exit_code, 0);
    const Child estimate = RunChild({HRG_ESTIMATE, session.string(), "--json"});
    ASSERT_EQ(estimate.exit_code, 0) << session;
    peak[i] = estimate.peak_rss_bytes;
  }
  const double extra_samples = (runs[1] - runs[0]) * 10'000.0;
  const double per_sample = (peak[1] - peak[0]) / extra_samples;
  EXPECT_LT(per_sample, kMaxBytesPerSessionSample)
      << "peak RSS " << peak[0] / 1e6 << " MB (6 runs), " << peak[1] / 1e6 << " MB (60 runs)";
  EXPECT_GT(per_sample, 0.0);
}

}  // namespace
