#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "hrgbench/config/sim_spec.hpp"

namespace hrgbench::app {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> ShippedSimSpecs() {
  std::vector<fs::path> files;
  for (const auto& entry :
       fs::directory_iterator(fs::path(HRGBENCH_SOURCE_DIR) / "bench_configs")) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with("sim-") && entry.path().extension() == ".toml")
      files.push_back(entry.path());
  }
  return files;
}

TEST(SimSpecLoader, EveryShippedSimSpecLoads) {
  const std::vector<fs::path> files = ShippedSimSpecs();
  ASSERT_GE(files.size(), 3u);
  for (const fs::path& file : files) {
    auto spec = LoadSimSpec(file);
    EXPECT_TRUE(spec.has_value()) << (spec ? "" : spec.error().ToString());
    if (spec) {
      EXPECT_FALSE(spec->runs.empty()) << file;
    }
  }
}

TEST(SimSpecLoader, PaperSpecIsThePapersExperiment) {
  auto spec = LoadSimSpec(fs::path(HRGBENCH_SOURCE_DIR) / "bench_configs/sim-paper.toml");
  ASSERT_TRUE(spec.has_value()) << spec.error().ToString();
  EXPECT_EQ(spec->delta, (estimator::Delta() << -0.001, 0.3, 0, 0, 0, 0).finished());
  EXPECT_EQ(spec->xi, (estimator::Xi() << 0.01, 0, 0, 0).finished());
  EXPECT_EQ(spec->sigma, 0.0);
  ASSERT_EQ(spec->runs.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    const double k = static_cast<double>(i);  // k - 1 of the paper
    const auto& run = spec->runs[i];
    EXPECT_EQ(run.a, 1.0);
    EXPECT_NEAR(run.b, -0.4 + 0.2 * k, 1e-15);
    EXPECT_NEAR(run.theta_rad, std::numbers::pi / 7.0 * k, 1e-15);
    EXPECT_NEAR(run.omega_rad_s, -1e-4 + 5e-5 * k, 1e-19);
    EXPECT_EQ(run.phi_rad, 0.0);
    EXPECT_EQ(run.sample_rate_hz, 100.0);
    EXPECT_EQ(run.duration_s, 10.0);
  }
}

TEST(SimSpecLoader, RateTableSpecIsProductionSize) {
  auto spec = LoadSimSpec(fs::path(HRGBENCH_SOURCE_DIR) / "bench_configs/sim-ratetable.toml");
  ASSERT_TRUE(spec.has_value()) << spec.error().ToString();
  ASSERT_EQ(spec->runs.size(), 6u);
  std::vector<double> omegas = spec->Omegas();
  std::sort(omegas.begin(), omegas.end());
  EXPECT_EQ(omegas, (std::vector<double>{-1.0, -0.3, -0.1, 0.1, 0.3, 1.0}));
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_NEAR(spec->runs[k].theta_rad, static_cast<double>(k) * std::numbers::pi / 12.0, 1e-15);
    EXPECT_EQ(spec->runs[k].b, 0.1 * static_cast<double>(k % 3)) << k;
    EXPECT_EQ(spec->runs[k].sample_rate_hz, 1000.0);
    EXPECT_EQ(spec->runs[k].duration_s, 100.0);
  }
  EXPECT_EQ(spec->sigma, 1e-4);
  EXPECT_TRUE((spec->xi.array() != 0.0).all());
}

// A valid spec, one key per line, so the cases below can say on which line the error must be.
const std::vector<std::string> kValidLines = {
    "[truth]",                                    // 1
    "delta = [-0.001, 0.3, 0.0, 0.0, 0.0, 0.0]",  // 2
    "xi = [0.01, 0.0, 0.0, 0.0]",                 // 3
    "[noise]",                                    // 4
    "sigma = 0.0",                                // 5
    "seed = 12345",                               // 6
    "[[runs]]",                                   // 7
    "omega_rad_s = -1e-4",                        // 8
    "a = 1.0",                                    // 9
    "b = -0.4",                                   // 10
    "theta_rad = 0.0",                            // 11
    "phi_rad = 0.0",                              // 12
    "sample_rate_hz = 100.0",                     // 13
    "duration_s = 10.0",                          // 14
};

std::string Join(const std::vector<std::string>& lines) {
  std::ostringstream text;
  for (const std::string& line : lines) text << line << '\n';
  return text.str();
}

// kValidLines with line `line` (1-based) replaced; an empty replacement leaves an empty line, so
// the other lines keep their numbers.
std::string WithLine(int line, const std::string& replacement) {
  std::vector<std::string> lines = kValidLines;
  lines.at(static_cast<std::size_t>(line - 1)) = replacement;
  return Join(lines);
}

TEST(SimSpecLoader, ValidTextLoads) {
  auto spec = ParseSimSpec(Join(kValidLines), "valid.toml");
  ASSERT_TRUE(spec.has_value()) << spec.error().ToString();
  EXPECT_EQ(spec->serial, "SIM-valid");
  EXPECT_EQ(spec->seed, 12345u);
  ASSERT_EQ(spec->runs.size(), 1u);
  EXPECT_EQ(spec->runs[0].omega_rad_s, -1e-4);
}

TEST(SimSpecLoader, DefaultsFillRunsAndRunsOverrideThem) {
  const std::string text = R"(
[truth]
delta = [-0.001, 0.3, 0, 0, 0, 0]
xi = [0, 0, 0, 0]
[defaults]
a = 2
b = 0.5
theta_rad = 0.25
phi_rad = 0.125
sample_rate_hz = 50
duration_s = 3
[[runs]]
omega_rad_s = 0.1
[[runs]]
omega_rad_s = -0.1
sample_rate_hz = 200.0
)";
  auto spec = ParseSimSpec(text, "defaults.toml");
  ASSERT_TRUE(spec.has_value()) << spec.error().ToString();
  ASSERT_EQ(spec->runs.size(), 2u);
  EXPECT_EQ(spec->runs[0].a, 2.0);
  EXPECT_EQ(spec->runs[0].b, 0.5);
  EXPECT_EQ(spec->runs[0].theta_rad, 0.25);
  EXPECT_EQ(spec->runs[0].phi_rad, 0.125);
  EXPECT_EQ(spec->runs[0].sample_rate_hz, 50.0);
  EXPECT_EQ(spec->runs[0].duration_s, 3.0);
  EXPECT_EQ(spec->runs[1].sample_rate_hz, 200.0);
  EXPECT_EQ(spec->sigma, 0.0);  // [noise] absent: noise-free
  EXPECT_EQ(spec->seed, 1u);
}

struct BadCase {
  std::string name;
  std::string text;
  std::size_t line;
  std::string key;
  std::string value;    // as written in the file; empty for a missing key
  std::string message;  // a fragment of the message
};

std::ostream& operator<<(std::ostream& out, const BadCase& c) { return out << c.name; }

class SimSpecLoaderBad : public ::testing::TestWithParam<BadCase> {};

TEST_P(SimSpecLoaderBad, ErrorNamesFileLineKeyAndValue) {
  const BadCase& c = GetParam();
  auto spec = ParseSimSpec(c.text, "bench_configs/bad.toml");
  ASSERT_FALSE(spec.has_value()) << c.name << " loaded";
  const ConfigError& error = spec.error();
  const std::string text = error.ToString();
  EXPECT_EQ(error.file, fs::path("bench_configs/bad.toml"));
  EXPECT_EQ(error.line, c.line) << text;
  EXPECT_EQ(error.key, c.key) << text;
  EXPECT_EQ(error.value, c.value) << text;
  EXPECT_NE(error.message.find(c.message), std::string::npos) << text;
  // And all of it in the one line the operator reads.
  EXPECT_TRUE(text.starts_with("bench_configs/bad.toml:" + std::to_string(c.line) + ": ")) << text;
  EXPECT_NE(text.find("'" + c.key + "'"), std::string::npos) << text;
  EXPECT_NE(text.find(c.value), std::string::npos) << text;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, SimSpecLoaderBad,
    ::testing::Values(
        BadCase{"UnknownRunKey", Join(kValidLines) + "gain = 2.0\n", 15, "runs[0].gain", "2.0",
                "unknown key"},
        BadCase{"MisspeltNoiseKey", WithLine(5, "sigmaa = 1e-4"), 5, "noise.sigmaa", "1e-4",
                "unknown key"},
        BadCase{"UnknownTable", Join(kValidLines) + "[calibration]\nx = 1\n", 15, "calibration",
                "[calibration]", "unknown key"},
        BadCase{"StringForNumber", WithLine(13, "sample_rate_hz = \"100\""), 13,
                "runs[0].sample_rate_hz", "\"100\"", "wrong type"},
        BadCase{"FloatSeed", WithLine(6, "seed = 1.5"), 6, "noise.seed", "1.5", "wrong type"},
        BadCase{"ScalarForArray", WithLine(2, "delta = 0.3"), 2, "truth.delta", "0.3",
                "wrong type"},
        BadCase{"ShortDelta", WithLine(2, "delta = [-0.001, 0.3, 0.0, 0.0, 0.0]"), 2, "truth.delta",
                "[-0.001, 0.3, 0.0, 0.0, 0.0]", "wrong length 5"},
        BadCase{"NegativeSampleRate", WithLine(13, "sample_rate_hz = -100.0"), 13,
                "runs[0].sample_rate_hz", "-100.0", "out of range: must be > 0"},
        BadCase{"ZeroDuration", WithLine(14, "duration_s = 0"), 14, "runs[0].duration_s", "0",
                "out of range"},
        BadCase{"NegativeSigma", WithLine(5, "sigma = -1e-4"), 5, "noise.sigma", "-1e-4",
                "out of range: must be >= 0"},
        BadCase{"NegativeSeed", WithLine(6, "seed = -3"), 6, "noise.seed", "-3", "out of range"},
        BadCase{"HugeXi", WithLine(3, "xi = [0.3, 0.0, 0.0, 0.0]"), 3, "truth.xi[0]", "0.3",
                "out of range"},
        BadCase{"NanOmega", WithLine(8, "omega_rad_s = nan"), 8, "runs[0].omega_rad_s", "nan",
                "out of range"},
        BadCase{"QuadratureAboveAmplitude", WithLine(10, "b = 1.5"), 10, "runs[0].b", "1.5",
                "|b| <= a"},
        BadCase{"TooManySamples", WithLine(14, "duration_s = 1e6"), 14, "runs[0].duration_s", "1e6",
                "at most 1e7"},
        BadCase{"TooFewSamples", WithLine(14, "duration_s = 0.01"), 14, "runs[0].duration_s",
                "0.01", "at least 2"},
        BadCase{"MissingOmega", WithLine(8, ""), 7, "runs[0].omega_rad_s", "", "missing"},
        BadCase{"MissingXi", WithLine(3, ""), 1, "truth.xi", "", "missing"},
        BadCase{"MisspeltTruthTable", WithLine(1, "[truht]"), 1, "truth", "", "missing"}),
    [](const ::testing::TestParamInfo<BadCase>& param_info) { return param_info.param.name; });

TEST(SimSpecLoader, MissingTruthTable) {
  std::vector<std::string> lines(kValidLines.begin() + 3, kValidLines.end());
  auto spec = ParseSimSpec(Join(lines), "bench_configs/bad.toml");
  ASSERT_FALSE(spec.has_value());
  EXPECT_EQ(spec.error().key, "truth");
  EXPECT_EQ(spec.error().line, 1u);
  EXPECT_NE(spec.error().message.find("missing"), std::string::npos);
}

TEST(SimSpecLoader, MissingRuns) {
  std::vector<std::string> lines(kValidLines.begin(), kValidLines.begin() + 6);
  auto spec = ParseSimSpec(Join(lines), "bench_configs/bad.toml");
  ASSERT_FALSE(spec.has_value());
  EXPECT_EQ(spec.error().key, "runs");
  EXPECT_NE(spec.error().ToString().find("missing"), std::string::npos);
}

TEST(SimSpecLoader, SyntaxErrorNamesTheLine) {
  auto spec = ParseSimSpec(WithLine(9, "a = = 1.0"), "bench_configs/bad.toml");
  ASSERT_FALSE(spec.has_value());
  EXPECT_EQ(spec.error().line, 9u);
  EXPECT_NE(spec.error().ToString().find("bench_configs/bad.toml:9:"), std::string::npos);
}

TEST(SimSpecLoader, UnreadableFile) {
  auto spec = LoadSimSpec("/nonexistent/spec.toml");
  ASSERT_FALSE(spec.has_value());
  EXPECT_NE(spec.error().ToString().find("/nonexistent/spec.toml"), std::string::npos);
}

}  // namespace
}  // namespace hrgbench::app
