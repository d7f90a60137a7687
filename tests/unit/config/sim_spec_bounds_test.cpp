// The config bounds (hrgbench/config/config_bounds.hpp) applied to simulation specs: a serial
// is a name, at most 1000 runs and a day of simulated free run, a path that is a directory says so.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "hrgbench/config/sim_spec.hpp"

namespace hrgbench::app {
namespace {

namespace fs = std::filesystem;

const fs::path kFile = "bench_configs/sim-bad.toml";

const std::string kHead = R"([session]
serial = "SIM-1"

[truth]
delta = [-0.001, 0.3, 0.0, 0.0, 0.0, 0.0]
xi = [0.01, 0.0, 0.0, 0.0]

[defaults]
a = 1.0
b = 0.0
theta_rad = 0.0
phi_rad = 0.0
sample_rate_hz = 1.0
duration_s = 10.0
)";
const std::string kRun = "\n[[runs]]\nomega_rad_s = 0.5\n";

TEST(SimSpecBounds, TheBaseLoads) {
  auto spec = ParseSimSpec(kHead + kRun, kFile);
  EXPECT_TRUE(spec) << spec.error().ToString();
}

TEST(SimSpecBounds, NulInTheSerialIsRefused) {
  std::string text = kHead + kRun;
  text.replace(text.find("\"SIM-1\""), 7, "\"SIM\\u0000-1\"");
  auto spec = ParseSimSpec(text, kFile);
  ASSERT_FALSE(spec);
  EXPECT_EQ(spec.error().ToString(),
            "bench_configs/sim-bad.toml:2: key 'session.serial' = \"SIM\\u0000-1\": out of range: "
            "control character U+0000 at byte 3; a name is printable text on one line");
}

TEST(SimSpecBounds, MoreThanAThousandRunsAreRefused) {
  std::string text = kHead;
  for (int i = 0; i < 1001; ++i) text += kRun;
  auto spec = ParseSimSpec(text, kFile);
  ASSERT_FALSE(spec);
  EXPECT_EQ(spec.error().key, "runs");
  EXPECT_EQ(spec.error().line, 16u);
  EXPECT_NE(spec.error().message.find("1001 [[runs]] tables"), std::string::npos)
      << spec.error().ToString();
}

TEST(SimSpecBounds, TotalDurationBeyondADayIsRefused) {
  std::string text = kHead + kRun + kRun;
  text.replace(text.find("duration_s = 10.0"), 17, "duration_s = 50000.0");
  auto spec = ParseSimSpec(text, kFile);
  ASSERT_FALSE(spec);
  EXPECT_EQ(spec.error().key, "defaults.duration_s");
  EXPECT_NE(spec.error().message.find("runs[0..1] last 100000 s in total"), std::string::npos)
      << spec.error().ToString();
}

// duration_s × sample_rate_hz beyond what a long long holds, and a total duration likewise: quoted
// as the doubles they are (they were cast: undefined behaviour, "-9223372036854775808 samples").
TEST(SimSpecBounds, AnAstronomicalSampleCountIsQuotedAsItIs) {
  std::string text = kHead + kRun;
  text.replace(text.find("duration_s = 10.0"), 17, "duration_s = 1e300");
  auto spec = ParseSimSpec(text, kFile);
  ASSERT_FALSE(spec);
  EXPECT_NE(spec.error().message.find("gives 1e+300 samples"), std::string::npos)
      << spec.error().ToString();
}

TEST(SimSpecBounds, AnAstronomicalTotalDurationIsQuotedAsItIs) {
  std::string text = kHead + kRun;
  text.replace(text.find("duration_s = 10.0"), 17, "duration_s = 1e300");
  text.replace(text.find("sample_rate_hz = 1.0"), 20, "sample_rate_hz = 1e-299");
  auto spec = ParseSimSpec(text, kFile);
  ASSERT_FALSE(spec);
  EXPECT_NE(spec.error().message.find("last 1e+300 s in total"), std::string::npos)
      << spec.error().ToString();
}

TEST(SimSpecBounds, PathThatIsADirectorySaysSo) {
  const fs::path dir =
      fs::temp_directory_path() / ("hrgbench_sim_spec_dir_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  auto spec = LoadSimSpec(dir);
  fs::remove_all(dir);
  ASSERT_FALSE(spec);
  EXPECT_EQ(spec.error().ToString(), dir.string() + ": is a directory, not a file");
}

}  // namespace
}  // namespace hrgbench::app
