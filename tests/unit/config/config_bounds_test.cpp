// The bounds on what a config file may say (hrgbench/config/config_bounds.hpp): names without
// control characters and of a sane length, waits and free-run time of at most a day, at most 1000
// runs, files of at most 1 MiB, and a path that is a directory named as such. Each error names
// file, line, key and value like every other config error.

#include "hrgbench/config/config_bounds.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "hrgbench/config/bench_configs.hpp"

namespace hrgbench::bench {
namespace {

using config_file::ConfigError;
using config_file::kMaxConfigFileBytes;
using config_file::kMaxRuns;

namespace fs = std::filesystem;

const fs::path kFile = "bench_configs/bad.toml";

const std::string kSequenceHead = R"([sequence]
name = "q"

[timeouts]
settle_s = 30.0

[defaults]
a = 1.0
b = 0.0
theta_rad = 0.0
free_run_s = 10.0
sample_rate_hz = 100
)";

const std::string kRun = "\n[[runs]]\nomega_rad_s = 0.5\n";

const std::string kLimits = "[limits]\nname = \"l\"\ndelta2 = [0.29, 0.31]\n";

void ExpectError(const ConfigError& error, std::size_t line, const std::string& key,
                 const std::string& value, const std::string& message_part) {
  EXPECT_EQ(error.file, kFile) << error.ToString();
  EXPECT_EQ(error.line, line) << error.ToString();
  EXPECT_EQ(error.key, key) << error.ToString();
  EXPECT_EQ(error.value, value) << error.ToString();
  EXPECT_NE(error.message.find(message_part), std::string::npos) << error.ToString();
}

TEST(ConfigBounds, TheBaseSequenceLoads) {
  auto sequence = ParseSequenceConfig(kSequenceHead + kRun, kFile);
  EXPECT_TRUE(sequence) << sequence.error().ToString();
}

// [adaptive] (issue 27 §1): off unless asked; min_runs within the sequence's runs.
TEST(ConfigBounds, AdaptiveStopIsReadAndItsMinimumRunsBounded) {
  auto plain = ParseSequenceConfig(kSequenceHead + kRun, kFile);
  ASSERT_TRUE(plain) << plain.error().ToString();
  EXPECT_FALSE(plain->adaptive.stop_when_decided);
  EXPECT_EQ(plain->adaptive.min_runs, 1);
  const std::string two_runs = kSequenceHead + kRun + kRun;
  auto on = ParseSequenceConfig(two_runs + "\n[adaptive]\nstop_when_decided = true\nmin_runs = 2\n",
                                kFile);
  ASSERT_TRUE(on) << on.error().ToString();
  EXPECT_TRUE(on->adaptive.stop_when_decided);
  EXPECT_EQ(on->adaptive.min_runs, 2);
  auto beyond = ParseSequenceConfig(two_runs + "\n[adaptive]\nmin_runs = 3\n", kFile);
  ASSERT_FALSE(beyond);
  EXPECT_EQ(beyond.error().key, "adaptive.min_runs") << beyond.error().ToString();
  EXPECT_EQ(beyond.error().value, "3") << beyond.error().ToString();
  EXPECT_NE(beyond.error().message.find("out of range"), std::string::npos)
      << beyond.error().ToString();
  auto zero = ParseSequenceConfig(two_runs + "\n[adaptive]\nmin_runs = 0\n", kFile);
  ASSERT_FALSE(zero);
  EXPECT_EQ(zero.error().key, "adaptive.min_runs") << zero.error().ToString();
  auto unknown = ParseSequenceConfig(two_runs + "\n[adaptive]\nstop_early = true\n", kFile);
  ASSERT_FALSE(unknown);
  EXPECT_NE(unknown.error().ToString().find("stop_when_decided, min_runs"), std::string::npos)
      << unknown.error().ToString();
  auto not_bool = ParseSequenceConfig(two_runs + "\n[adaptive]\nstop_when_decided = 1\n", kFile);
  ASSERT_FALSE(not_bool);
  EXPECT_EQ(not_bool.error().key, "adaptive.stop_when_decided") << not_bool.error().ToString();
  // The interim looks' coverage factor: absent unless written, and within [1, 6].
  EXPECT_FALSE(on->adaptive.interim_coverage_factor.has_value());
  auto interim =
      ParseSequenceConfig(two_runs + "\n[adaptive]\ninterim_coverage_factor = 3\n", kFile);
  ASSERT_TRUE(interim) << interim.error().ToString();
  EXPECT_EQ(interim->adaptive.interim_coverage_factor, 3.0);
  auto too_large =
      ParseSequenceConfig(two_runs + "\n[adaptive]\ninterim_coverage_factor = 7\n", kFile);
  ASSERT_FALSE(too_large);
  EXPECT_EQ(too_large.error().key, "adaptive.interim_coverage_factor")
      << too_large.error().ToString();
  EXPECT_EQ(too_large.error().value, "7") << too_large.error().ToString();
}

// [adaptive] look_interval_s: looks within runs, planned as the sequencer takes them.
TEST(ConfigBounds, LooksWithinRunsArePlannedAndBounded) {
  // A 10 s run, then a 30 s one.
  const std::string runs = kSequenceHead + kRun + kRun + "free_run_s = 30.0\n";
  auto after_runs =
      ParseSequenceConfig(runs + "\n[adaptive]\nstop_when_decided = true\nmin_runs = 1\n", kFile);
  ASSERT_TRUE(after_runs) << after_runs.error().ToString();
  EXPECT_EQ(after_runs->adaptive.look_interval_s, 0.0);
  EXPECT_EQ(after_runs->InterimLookFractions(), std::vector<double>{0.25});  // after run 1
  auto within = ParseSequenceConfig(
      runs + "\n[adaptive]\nstop_when_decided = true\nmin_runs = 1\nlook_interval_s = 3\n", kFile);
  ASSERT_TRUE(within) << within.error().ToString();
  EXPECT_EQ(within->adaptive.look_interval_s, 3.0);
  // Run 1 at 3 and 6 s (not at 9 s: within half an interval of its end); after run 1; run 2 from
  // 12 s (the first multiple of 3 s as long as run 1) to 27 s, of 40 s in all.
  const std::vector<double> looks = within->InterimLookFractions();
  const std::vector<double> expected = {3, 6, 10, 22, 25, 28, 31, 34, 37};
  ASSERT_EQ(looks.size(), expected.size());
  for (std::size_t i = 0; i < looks.size(); ++i)
    EXPECT_NEAR(looks[i], expected[i] / 40.0, 1e-12) << i;
  EXPECT_EQ(FirstLookWithinRunS(3.0, 0.0), 3.0);
  EXPECT_EQ(FirstLookWithinRunS(3.0, 10.0), 12.0);
  EXPECT_EQ(FirstLookWithinRunS(5.0, 20.0), 20.0);
  EXPECT_EQ(FirstLookWithinRunS(0.0, 20.0), 0.0);
  // From min_runs on only: run 2's six.
  auto from_second = ParseSequenceConfig(
      runs + "\n[adaptive]\nstop_when_decided = true\nmin_runs = 2\nlook_interval_s = 3\n", kFile);
  ASSERT_TRUE(from_second) << from_second.error().ToString();
  EXPECT_EQ(from_second->InterimLookFractions().size(), 6u);
  // Off: no looks at all.
  auto off = ParseSequenceConfig(runs + "\n[adaptive]\nlook_interval_s = 3\n", kFile);
  ASSERT_TRUE(off) << off.error().ToString();
  EXPECT_TRUE(off->InterimLookFractions().empty());
  auto too_often = ParseSequenceConfig(runs + "\n[adaptive]\nlook_interval_s = 0.5\n", kFile);
  ASSERT_FALSE(too_often);
  EXPECT_EQ(too_often.error().key, "adaptive.look_interval_s") << too_often.error().ToString();
  EXPECT_EQ(too_often.error().value, "0.5") << too_often.error().ToString();
  // More looks than an estimate each can be afforded: a 10 s run, then 100 runs of 30 s looked at
  // every 2 s from 10 s on (10 looks each) and after each but the last.
  std::string many = kSequenceHead + kRun;
  for (int i = 0; i < 100; ++i) many += kRun + "free_run_s = 30.0\n";
  auto too_many = ParseSequenceConfig(
      many + "\n[adaptive]\nstop_when_decided = true\nmin_runs = 2\nlook_interval_s = 2\n", kFile);
  ASSERT_FALSE(too_many);
  EXPECT_EQ(too_many.error().key, "adaptive.look_interval_s") << too_many.error().ToString();
  EXPECT_NE(too_many.error().message.find("1099 interim looks"), std::string::npos)
      << too_many.error().ToString();
}

// [adaptive] next_run: the plan's order unless the most informative run is asked for.
TEST(ConfigBounds, TheNextRunIsThePlansUnlessAsked) {
  const std::string two_runs = kSequenceHead + kRun + kRun;
  auto plain = ParseSequenceConfig(two_runs + "\n[adaptive]\nstop_when_decided = true\n", kFile);
  ASSERT_TRUE(plain) << plain.error().ToString();
  EXPECT_FALSE(plain->adaptive.most_informative_next);
  auto informative =
      ParseSequenceConfig(two_runs + "\n[adaptive]\nnext_run = \"most_informative\"\n", kFile);
  ASSERT_TRUE(informative) << informative.error().ToString();
  EXPECT_TRUE(informative->adaptive.most_informative_next);
  auto unknown = ParseSequenceConfig(two_runs + "\n[adaptive]\nnext_run = \"shortest\"\n", kFile);
  ASSERT_FALSE(unknown);
  EXPECT_EQ(unknown.error().key, "adaptive.next_run") << unknown.error().ToString();
}

TEST(ConfigBounds, NulInANameIsRefused) {
  auto limits = ParseLimitsConfig("[limits]\nname = \"l\\u0000x\"\n", kFile);
  ASSERT_FALSE(limits);
  ExpectError(limits.error(), 2, "limits.name", "\"l\\u0000x\"",
              "control character U+0000 at byte 1");
}

TEST(ConfigBounds, LineFeedInAHostIsRefused) {
  auto station = ParseStationConfig(R"([station]
name = "s"
kind = "real"
[site]
latitude_deg = 45.0
[gyro]
can_interface = "can0"
[table]
transport = "tcp"
host = "192.0.2.1\nX-Forged: 1"
)",
                                    kFile);
  ASSERT_FALSE(station);
  ExpectError(station.error(), 10, "table.host", "\"192.0.2.1\\nX-Forged: 1\"",
              "control character U+000A");
}

TEST(ConfigBounds, OneMegabyteNameIsRefused) {
  const std::string name(1'000'000, 'x');
  auto sequence = ParseSequenceConfig("[sequence]\nname = \"" + name + "\"\n" + kRun, kFile);
  ASSERT_FALSE(sequence);
  ExpectError(sequence.error(), 2, "sequence.name", "\"" + name.substr(0, 79) + "...",
              "1000000 bytes long; a name has at most 255");
}

TEST(ConfigBounds, DescriptionMayHoldLineFeedsButNotOtherControlCharacters) {
  auto ok = ParseLimitsConfig(kLimits + "description = \"\"\"two\n\tlines\"\"\"\n", kFile);
  EXPECT_TRUE(ok) << ok.error().ToString();
  auto bad = ParseLimitsConfig(kLimits + "description = \"bell\\u0007\"\n", kFile);
  ASSERT_FALSE(bad);
  ExpectError(bad.error(), 4, "limits.description", "\"bell\\u0007\"", "control character U+0007");
}

TEST(ConfigBounds, SettleTimeoutOf1e12SecondsIsRefused) {
  std::string text = kSequenceHead + kRun;
  text.replace(text.find("settle_s = 30.0"), 15, "settle_s = 1e12");
  auto sequence = ParseSequenceConfig(text, kFile);
  ASSERT_FALSE(sequence);
  ExpectError(sequence.error(), 5, "timeouts.settle_s", "1e12", "must be in (0, 3600] s");
}

TEST(ConfigBounds, ExciteTimeoutOf1e12SecondsIsRefused) {
  std::string text = kSequenceHead + kRun;
  text.replace(text.find("settle_s = 30.0"), 15, "settle_s = 30.0\nexcite_s = 1e12");
  auto sequence = ParseSequenceConfig(text, kFile);
  ASSERT_FALSE(sequence);
  ExpectError(sequence.error(), 6, "timeouts.excite_s", "1e12", "must be in (0, 3600] s");
}

TEST(ConfigBounds, WarmupTimeoutBeyondTwoDaysIsRefused) {
  auto sequence = ParseSequenceConfig(kSequenceHead + "[warmup]\ntimeout_s = 1e12\n" + kRun, kFile);
  ASSERT_FALSE(sequence);
  ExpectError(sequence.error(), 14, "warmup.timeout_s", "1e12", "must be in (0, 172800] s");
}

TEST(ConfigBounds, FaultTimeBeyondADayIsRefused) {
  auto station = ParseStationConfig(R"([station]
name = "s"
kind = "simulated"
[site]
latitude_deg = 45.0
[simulated]
faster_than_real_time = true
[simulated.faults]
table_fault_after_s = 1e12
)",
                                    kFile);
  ASSERT_FALSE(station);
  ExpectError(station.error(), 9, "simulated.faults.table_fault_after_s", "1e12",
              "must be in [0, 86400] s");
}

TEST(ConfigBounds, A100006RunSequenceIsRefused) {
  // The issue's file: 100 006 runs of 100 s, 1e7 s of free run. At 2.8 MB it is refused for its
  // size before it is parsed.
  std::string text = kSequenceHead;
  for (int i = 0; i < 100'006; ++i) text += kRun;
  auto sequence = ParseSequenceConfig(text, kFile);
  ASSERT_FALSE(sequence);
  EXPECT_EQ(sequence.error().ToString(),
            "bench_configs/bad.toml: file too large: 2800301 bytes (a config file has at most "
            "1048576)");
}

TEST(ConfigBounds, MoreThanAThousandRunsAreRefusedBeforeAnyIsRead) {
  std::string text = kSequenceHead;
  for (std::size_t i = 0; i <= kMaxRuns; ++i) text += kRun;
  auto sequence = ParseSequenceConfig(text, kFile);
  ASSERT_FALSE(sequence);
  ExpectError(sequence.error(), 14, "runs", "",
              "1001 [[runs]] tables; a sequence has at most 1000");
}

TEST(ConfigBounds, TotalFreeRunBeyondADayIsRefusedAtTheRunThatCrossesIt) {
  // Each run alone is fine (50 000 samples); the second brings the total to 100 000 s.
  std::string text = kSequenceHead + kRun + kRun + kRun;
  text.replace(text.find("free_run_s = 10.0"), 17, "free_run_s = 50000.0");
  text.replace(text.find("sample_rate_hz = 100"), 20, "sample_rate_hz = 1");
  auto sequence = ParseSequenceConfig(text, kFile);
  ASSERT_FALSE(sequence);
  ExpectError(sequence.error(), 11, "defaults.free_run_s", "50000.0",
              "runs[0..1] free-run 100000 s in total; a sequence free-runs at most 86400 s");
}

// free_run_s × sample_rate_hz beyond what a long long holds: the message quotes the product as the
// double it is (it once cast it: undefined behaviour, "-9223372036854775808 samples").
TEST(ConfigBounds, AnAstronomicalSampleCountIsQuotedAsItIs) {
  std::string text = kSequenceHead + kRun;
  text.replace(text.find("free_run_s = 10.0"), 17, "free_run_s = 1e300");
  auto sequence = ParseSequenceConfig(text, kFile);
  ASSERT_FALSE(sequence);
  EXPECT_EQ(sequence.error().key, "defaults.free_run_s");
  EXPECT_NE(sequence.error().message.find("gives 1e+302 samples"), std::string::npos)
      << sequence.error().ToString();
}

TEST(ConfigBounds, OversizedTextIsRefused) {
  const std::string text = kLimits + "#" + std::string(kMaxConfigFileBytes, 'x') + "\n";
  auto limits = ParseLimitsConfig(text, kFile);
  ASSERT_FALSE(limits);
  EXPECT_EQ(limits.error().line, 0u);
  EXPECT_NE(limits.error().message.find("file too large"), std::string::npos)
      << limits.error().ToString();
}

class ConfigPathTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("hrgbench_config_bounds_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "limits-dir.toml");
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
};

TEST_F(ConfigPathTest, LimitsPathThatIsADirectorySaysSo) {
  const fs::path limits = dir_ / "limits-dir.toml";
  auto loaded = LoadLimitsConfig(limits);
  ASSERT_FALSE(loaded);
  EXPECT_EQ(loaded.error().ToString(), limits.string() + ": is a directory, not a file");
  const fs::path configs = fs::path(HRGBENCH_SOURCE_DIR) / "bench_configs";
  auto all =
      LoadBenchConfigs(configs / "station-sim.toml", configs / "sequence-paper.toml", limits);
  ASSERT_FALSE(all);
  EXPECT_EQ(all.error().ToString(), limits.string() + ": is a directory, not a file");
}

TEST_F(ConfigPathTest, StationAndSequencePathsThatAreDirectoriesSaySo) {
  const fs::path path = dir_ / "limits-dir.toml";
  auto station = LoadStationConfig(path);
  ASSERT_FALSE(station);
  EXPECT_NE(station.error().message.find("is a directory"), std::string::npos);
  auto sequence = LoadSequenceConfig(path);
  ASSERT_FALSE(sequence);
  EXPECT_NE(sequence.error().message.find("is a directory"), std::string::npos);
}

TEST_F(ConfigPathTest, OversizedFileIsRefusedUnread) {
  const fs::path path = dir_ / "limits-big.toml";
  { std::ofstream(path) << kLimits; }
  fs::resize_file(path, std::uintmax_t{64} << 20);  // sparse
  auto limits = LoadLimitsConfig(path);
  ASSERT_FALSE(limits);
  EXPECT_EQ(limits.error().ToString(),
            path.string() + ": file too large: 67108864 bytes (a config file has at most 1048576)");
}

}  // namespace
}  // namespace hrgbench::bench
