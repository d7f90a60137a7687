// Every kind of malformed config gets its error, naming file, line, key and value (STYLE rule 10).
// Each case changes one line of a valid file; the expected line is where the changed text is.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "hrgbench/config/bench_configs.hpp"

namespace hrgbench::bench {
namespace {

using config_file::ConfigError;

const std::string kStationText = R"([station]
name = "t"
kind = "real"

[site]
latitude_deg = 45.0
axis_enu = [0.0, 0.0, 1.0]

[gyro]
can_interface = "vcan0"
bitrate = 500000
ack_timeout_ms = 50

[table]
transport = "tcp"
host = "192.0.2.1"
port = 502
unit_id = 1
watchdog_ms = 1000
heartbeat_period_ms = 200
max_rate_rad_s = 2.0
accel_rad_s2 = 1.0

[realtime]
priority = 0
cpu = -1
lock_memory = false
)";

const std::string kSimStationText = R"([station]
name = "s"
kind = "simulated"

[site]
latitude_deg = 45.0

[simulated]
faster_than_real_time = true
sigma = 1e-4
seed = 3

[simulated.faults]
gyro_drop_every_nth_sample = 0
)";

const std::string kSequenceText = R"([sequence]
name = "q"

[settle]
rate_tolerance_rad_s = 1e-3
dwell_s = 1.0

[timeouts]
settle_s = 30.0

[drift]
action = "flag"

[capture]
max_sequence_gaps = 0

[defaults]
a = 1.0
free_run_s = 10.0
sample_rate_hz = 100

[[runs]]
omega_rad_s = 0.5
b = 0.1
theta_rad = 0.0

[[runs]]
omega_rad_s = -0.5
b = 0.2
theta_rad = 0.5
)";

const std::string kLimitsText = R"([limits]
name = "l"
delta2 = [0.29, 0.31]
xi1 = [-0.02, 0.02]
residual_rms = [0.0, 5e-4]
)";

// The same with a decision rule (config/decision_rule.hpp).
const std::string kLimitsDecisionText = kLimitsText + R"(
[decision]
rule = "guarded_acceptance_retest"
coverage_factor = 2.0
)";

// The same with the tuning's limits (LimitsConfig::tune).
const std::string kLimitsTuneText = kLimitsText + R"(
[tune]
rate_error_deg_h = 1.0
scale_factor_ppm = 10.0
scale_factor_asymmetry_ppm = 5.0
min_improvement = 100
)";

enum class Kind { kStation, kSequence, kLimits };

struct Case {
  const char* name;
  Kind kind;
  const std::string* base;
  std::string from;   // text replaced in the base (must occur once)
  std::string to;     // replacement; its first line is where the error must be
  std::string key;    // expected key path
  std::string value;  // expected value text ("" when missing)
  std::string message_part;
  std::size_t line = 0;  // 0: the line of `to` in the mutated text
};

std::size_t LineOfText(const std::string& text, const std::string& needle) {
  const std::size_t at = text.find(needle);
  if (at == std::string::npos) return 0;
  return 1 + static_cast<std::size_t>(
                 std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
}

std::string Mutate(const std::string& base, const std::string& from, const std::string& to) {
  const std::size_t at = base.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  EXPECT_EQ(base.find(from, at + 1), std::string::npos) << "ambiguous: " << from;
  std::string text = base;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

std::expected<void, ConfigError> Parse(Kind kind, const std::string& text,
                                       const std::filesystem::path& file) {
  switch (kind) {
    case Kind::kStation:
      if (auto r = ParseStationConfig(text, file); !r) return std::unexpected(r.error());
      return {};
    case Kind::kSequence:
      if (auto r = ParseSequenceConfig(text, file); !r) return std::unexpected(r.error());
      return {};
    case Kind::kLimits:
      if (auto r = ParseLimitsConfig(text, file); !r) return std::unexpected(r.error());
      return {};
  }
  return {};
}

TEST(MalformedConfigs, BasesAreValid) {
  EXPECT_TRUE(Parse(Kind::kStation, kStationText, "s.toml").has_value());
  EXPECT_TRUE(Parse(Kind::kStation, kSimStationText, "s.toml").has_value());
  EXPECT_TRUE(Parse(Kind::kSequence, kSequenceText, "q.toml").has_value());
  EXPECT_TRUE(Parse(Kind::kLimits, kLimitsText, "l.toml").has_value());
  auto tune = ParseLimitsConfig(kLimitsTuneText, "l.toml");
  ASSERT_TRUE(tune.has_value()) << tune.error().ToString();
  EXPECT_EQ(tune->tune.rate_error_deg_h, 1.0);
  EXPECT_EQ(tune->tune.scale_factor_ppm, 10.0);
  EXPECT_EQ(tune->tune.scale_factor_asymmetry_ppm, 5.0);
  EXPECT_FALSE(tune->tune.bias_deg_h.has_value());
  EXPECT_EQ(tune->tune.min_improvement, 100.0);
  EXPECT_EQ(tune->tune.line, 7u);
  auto plain = ParseLimitsConfig(kLimitsText, "l.toml");
  ASSERT_TRUE(plain.has_value());
  EXPECT_EQ(plain->tune.line, 0u);  // absent: nothing judged but the issue's 100x
  EXPECT_EQ(plain->tune.min_improvement, 100.0);
  EXPECT_TRUE(Parse(Kind::kLimits, kLimitsDecisionText, "l.toml").has_value());
}

const std::vector<Case>& Cases() {
  static const std::vector<Case> cases = {
      // Unknown keys.
      {"StationUnknownKey", Kind::kStation, &kStationText, "port = 502", "port = 502\nprot = 5",
       "table.prot", "5", "unknown key", 18},
      {"StationUnknownTable", Kind::kStation, &kStationText, "[realtime]", "[realtim]", "realtim",
       "[realtim]", "unknown key"},
      {"SequenceUnknownRunKey", Kind::kSequence, &kSequenceText, "theta_rad = 0.0\n",
       "theta_rad = 0.0\nomega = 1\n", "runs[0].omega", "1", "unknown key", 26},
      {"LimitsUnknownParameter", Kind::kLimits, &kLimitsText, "xi1 = [-0.02, 0.02]",
       "xi5 = [-0.02, 0.02]", "limits.xi5", "[-0.02, 0.02]", "unknown key"},
      // Wrong types.
      {"StationPortIsAString", Kind::kStation, &kStationText, "port = 502", "port = \"502\"",
       "table.port", "\"502\"", "wrong type: expected an integer in [1, 65535]"},
      {"StationPortIsAFloat", Kind::kStation, &kStationText, "port = 502", "port = 502.0",
       "table.port", "502.0", "wrong type"},
      {"StationLockMemoryIsAnInteger", Kind::kStation, &kStationText, "lock_memory = false",
       "lock_memory = 0", "realtime.lock_memory", "0", "wrong type: expected a boolean"},
      {"SequenceOmegaIsAString", Kind::kSequence, &kSequenceText, "omega_rad_s = 0.5",
       "omega_rad_s = \"fast\"", "runs[0].omega_rad_s", "\"fast\"", "wrong type"},
      {"LimitsRangeIsANumber", Kind::kLimits, &kLimitsText, "delta2 = [0.29, 0.31]", "delta2 = 0.3",
       "limits.delta2", "0.3", "wrong type: expected an array of 2 numbers"},
      // Out of range.
      {"StationLatitudeOutOfRange", Kind::kStation, &kStationText, "latitude_deg = 45.0",
       "latitude_deg = 95.0", "site.latitude_deg", "95.0", "out of range: must be in [-90, 90]"},
      {"StationPriorityOutOfRange", Kind::kStation, &kStationText, "priority = 0", "priority = 100",
       "realtime.priority", "100", "out of range: must be an integer in [0, 99]"},
      {"StationAxisNotUnit", Kind::kStation, &kStationText, "axis_enu = [0.0, 0.0, 1.0]",
       "axis_enu = [0.0, 0.5, 1.0]", "site.axis_enu", "[0.0, 0.5, 1.0]", "unit vector"},
      {"StationHeartbeatAboveHalfWatchdog", Kind::kStation, &kStationText,
       "heartbeat_period_ms = 200", "heartbeat_period_ms = 600", "table.heartbeat_period_ms", "600",
       "watchdog_ms / 2"},
      {"StationAccelAboveMax", Kind::kStation, &kStationText, "accel_rad_s2 = 1.0",
       "accel_rad_s2 = 6.0", "table.accel_rad_s2", "6.0", "max_accel_rad_s2"},
      {"SequenceNegativeFreeRun", Kind::kSequence, &kSequenceText, "free_run_s = 10.0",
       "free_run_s = -1.0", "defaults.free_run_s", "-1.0", "out of range: must be > 0"},
      {"SequenceFractionalSampleRate", Kind::kSequence, &kSequenceText, "sample_rate_hz = 100",
       "sample_rate_hz = 100.5", "defaults.sample_rate_hz", "100.5", "whole number of Hz"},
      {"SequenceQuadratureNotBelowAmplitude", Kind::kSequence, &kSequenceText, "b = 0.2", "b = 1.0",
       "runs[1].b", "1.0", "|b| < a"},
      {"SequenceDwellLongerThanSettleTimeout", Kind::kSequence, &kSequenceText, "settle_s = 30.0",
       "settle_s = 0.5", "timeouts.settle_s", "0.5", "settle.dwell_s"},
      {"LimitsMinAboveMax", Kind::kLimits, &kLimitsText, "delta2 = [0.29, 0.31]",
       "delta2 = [0.31, 0.29]", "limits.delta2", "[0.31, 0.29]", "min <= max"},
      {"LimitsNegativeRms", Kind::kLimits, &kLimitsText, "residual_rms = [0.0, 5e-4]",
       "residual_rms = [-1.0, 5e-4]", "limits.residual_rms", "[-1.0, 5e-4]", "min must be >= 0"},
      // Missing required keys (reported at the table's header line).
      {"StationMissingCanInterface", Kind::kStation, &kStationText, "can_interface = \"vcan0\"\n",
       "", "gyro.can_interface", "", "missing", 9},
      {"StationMissingHostForTcp", Kind::kStation, &kStationText, "host = \"192.0.2.1\"\n", "",
       "table.host", "", "missing", 14},
      {"StationMissingLatitude", Kind::kStation, &kStationText, "latitude_deg = 45.0\n", "",
       "site.latitude_deg", "", "missing", 5},
      {"SequenceMissingOmega", Kind::kSequence, &kSequenceText, "omega_rad_s = -0.5\n", "",
       "runs[1].omega_rad_s", "", "missing", 27},
      {"LimitsMissingName", Kind::kLimits, &kLimitsText, "name = \"l\"\n", "", "limits.name", "",
       "missing", 1},
      // Bad enum strings.
      {"StationBadKind", Kind::kStation, &kStationText, "kind = \"real\"", "kind = \"rael\"",
       "station.kind", "\"rael\"", "must be one of \"simulated\", \"real\""},
      {"StationBadTransport", Kind::kStation, &kStationText, "transport = \"tcp\"",
       "transport = \"udp\"", "table.transport", "\"udp\"", "must be one of \"tcp\", \"rtu\""},
      {"SequenceBadDriftAction", Kind::kSequence, &kSequenceText, "action = \"flag\"",
       "action = \"warn\"", "drift.action", "\"warn\"", "must be one of \"flag\", \"reject\""},
      // The decision rule.
      {"LimitsBadDecisionRule", Kind::kLimits, &kLimitsDecisionText,
       "rule = \"guarded_acceptance_retest\"", "rule = \"guarded\"", "decision.rule", "\"guarded\"",
       "must be one of \"guarded_acceptance_retest\", \"guarded_acceptance_reject\", "
       "\"simple_acceptance\""},
      {"LimitsCoverageFactorBelowOne", Kind::kLimits, &kLimitsDecisionText, "coverage_factor = 2.0",
       "coverage_factor = 0.5", "decision.coverage_factor", "0.5",
       "out of range: must be in [1, 6]"},
      {"LimitsCoverageFactorAboveSix", Kind::kLimits, &kLimitsDecisionText, "coverage_factor = 2.0",
       "coverage_factor = 10", "decision.coverage_factor", "10", "in [1, 6]"},
      {"LimitsCoverageFactorIsAString", Kind::kLimits, &kLimitsDecisionText,
       "coverage_factor = 2.0", "coverage_factor = \"2\"", "decision.coverage_factor", "\"2\"",
       "wrong type"},
      {"LimitsRatioWithAGuardedRule", Kind::kLimits, &kLimitsDecisionText, "coverage_factor = 2.0",
       "max_uncertainty_ratio = 0.25", "decision.max_uncertainty_ratio", "0.25",
       "only with rule = \"simple_acceptance\""},
      {"LimitsRatioOutOfRange", Kind::kLimits, &kLimitsDecisionText,
       "rule = \"guarded_acceptance_retest\"",
       "rule = \"simple_acceptance\"\nmax_uncertainty_ratio = 1.5",
       "decision.max_uncertainty_ratio", "1.5", "in (0, 1]", 9},
      {"LimitsDecisionUnknownKey", Kind::kLimits, &kLimitsDecisionText, "coverage_factor = 2.0",
       "k = 2.0", "decision.k", "2.0", "unknown key"},
      // The tuning's limits.
      {"LimitsTuneRateErrorZero", Kind::kLimits, &kLimitsTuneText, "rate_error_deg_h = 1.0",
       "rate_error_deg_h = 0", "tune.rate_error_deg_h", "0", "in (0, 1e6]"},
      {"LimitsTuneScaleFactorIsARange", Kind::kLimits, &kLimitsTuneText, "scale_factor_ppm = 10.0",
       "scale_factor_ppm = [-10, 10]", "tune.scale_factor_ppm", "[-10, 10]", "wrong type"},
      {"LimitsTuneImprovementBelowOne", Kind::kLimits, &kLimitsTuneText, "min_improvement = 100",
       "min_improvement = 0.5", "tune.min_improvement", "0.5", "in [1, 1e9]"},
      {"LimitsTuneUnknownKey", Kind::kLimits, &kLimitsTuneText, "min_improvement = 100",
       "drift_deg_h = 1", "tune.drift_deg_h", "1", "unknown key"},
      // Keys that do not apply to the station's kind or transport.
      {"StationRtuKeyWithTcp", Kind::kStation, &kStationText, "port = 502", "baud = 9600",
       "table.baud", "9600", "only to transport = \"rtu\""},
      {"SimStationCanInterface", Kind::kStation, &kSimStationText, "[simulated]\n",
       "[gyro]\ncan_interface = \"can0\"\n\n[simulated]\n", "gyro.can_interface", "\"can0\"",
       "only to kind = \"real\"", 9},
      {"SimStationTimeScaleWhenFaster", Kind::kStation, &kSimStationText, "sigma = 1e-4",
       "time_scale = 2.0", "simulated.time_scale", "2.0", "faster_than_real_time = false"},
      {"SimStationForcerErrorTooLarge", Kind::kStation, &kSimStationText, "sigma = 1e-4",
       "forcer_errors = [0.2, 0.0, 0.0, 0.0, 0.0]", "simulated.forcer_errors[0]", "0.2",
       "in [-0.1, 0.1]"},
      {"SimStationForcerErrorsNotFive", Kind::kStation, &kSimStationText, "sigma = 1e-4",
       "forcer_errors = [0.001, 0.0]", "simulated.forcer_errors", "[0.001, 0.0]", ""},
      {"SimStationDropEveryOne", Kind::kStation, &kSimStationText, "gyro_drop_every_nth_sample = 0",
       "gyro_drop_every_nth_sample = 1", "simulated.faults.gyro_drop_every_nth_sample", "1",
       "would drop every sample"},
  };
  return cases;
}

// gtest prints a failing parameter by name, not as bytes.
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class MalformedConfig : public ::testing::TestWithParam<Case> {};

TEST_P(MalformedConfig, ErrorNamesFileLineKeyAndValue) {
  const Case& c = GetParam();
  const std::string text = Mutate(*c.base, c.from, c.to);
  const std::filesystem::path file = "bench_configs/bad.toml";
  auto result = Parse(c.kind, text, file);
  ASSERT_FALSE(result.has_value()) << "accepted:\n" << text;
  const ConfigError& error = result.error();
  const std::size_t line = c.line != 0 ? c.line : LineOfText(text, c.to);
  EXPECT_EQ(error.file, file);
  EXPECT_EQ(error.line, line) << error.ToString();
  EXPECT_EQ(error.key, c.key) << error.ToString();
  EXPECT_EQ(error.value, c.value) << error.ToString();
  EXPECT_NE(error.message.find(c.message_part), std::string::npos) << error.ToString();
  // ToString carries every part.
  const std::string shown = error.ToString();
  EXPECT_NE(shown.find("bench_configs/bad.toml:" + std::to_string(line) + ": key '" + c.key + "'"),
            std::string::npos)
      << shown;
  if (!c.value.empty()) {
    EXPECT_NE(shown.find(" = " + c.value + ": "), std::string::npos) << shown;
  }
}

INSTANTIATE_TEST_SUITE_P(All, MalformedConfig, ::testing::ValuesIn(Cases()),
                         [](const ::testing::TestParamInfo<Case>& param_info) {
                           return std::string(param_info.param.name);
                         });

TEST(MalformedConfigs, SyntaxErrorNamesFileAndLine) {
  auto result =
      ParseSequenceConfig(Mutate(kSequenceText, "dwell_s = 1.0", "dwell_s = = 1.0"), "q.toml");
  ASSERT_FALSE(result.has_value());
  EXPECT_EQ(result.error().line, 6u);
  EXPECT_NE(result.error().message.find("TOML syntax error"), std::string::npos);
}

TEST(MalformedConfigs, UnreadableFileIsNamed) {
  auto result = LoadStationConfig("/nonexistent/station-x.toml");
  ASSERT_FALSE(result.has_value());
  EXPECT_EQ(result.error().file, "/nonexistent/station-x.toml");
  EXPECT_EQ(result.error().ToString(), "/nonexistent/station-x.toml: cannot open the file");
}

// Cross-file checks (LoadBenchConfigs / CheckBenchConfigs).
BenchConfigs Combine(const std::string& station, const std::string& sequence,
                     const std::string& limits) {
  BenchConfigs configs;
  configs.station = ParseStationConfig(station, "s.toml").value();
  configs.sequence = ParseSequenceConfig(sequence, "q.toml").value();
  configs.limits = ParseLimitsConfig(limits, "l.toml").value();
  return configs;
}

TEST(CrossChecks, ValidCombinationPasses) {
  EXPECT_TRUE(CheckBenchConfigs(Combine(kStationText, kSequenceText, kLimitsText)).has_value());
}

TEST(CrossChecks, RateAboveTheStationsLimitIsNamedInTheSequence) {
  const std::string sequence = Mutate(kSequenceText, "omega_rad_s = -0.5", "omega_rad_s = -2.5");
  auto result = CheckBenchConfigs(Combine(kStationText, sequence, kLimitsText));
  ASSERT_FALSE(result.has_value());
  EXPECT_EQ(result.error().file, "q.toml");
  EXPECT_EQ(result.error().line, LineOfText(sequence, "omega_rad_s = -2.5"));
  EXPECT_EQ(result.error().key, "runs[1].omega_rad_s");
  EXPECT_EQ(result.error().value, "-2.5");
  EXPECT_NE(result.error().message.find("table.max_rate_rad_s = 2"), std::string::npos);
}

TEST(CrossChecks, SampleRateAboveClassicCanNeedsFd) {
  const std::string sequence =
      Mutate(kSequenceText, "sample_rate_hz = 100", "sample_rate_hz = 4000");
  auto result = CheckBenchConfigs(Combine(kStationText, sequence, kLimitsText));
  ASSERT_FALSE(result.has_value());
  EXPECT_EQ(result.error().key, "runs[0].sample_rate_hz");
  EXPECT_EQ(result.error().line, LineOfText(sequence, "sample_rate_hz = 4000"));
  const std::string fd_station =
      Mutate(kStationText, "bitrate = 500000", "bitrate = 500000\nfd = true");
  EXPECT_TRUE(CheckBenchConfigs(Combine(fd_station, sequence, kLimitsText)).has_value());
}

// With gyro.fd = true the ceiling is CAN FD's, named as such (the plan is judged against the
// transport the station will use: simulated stations too, which ignored fd before).
TEST(CrossChecks, SampleRateAboveCanFdIsNamed) {
  const std::string fd_station =
      Mutate(kStationText, "bitrate = 500000", "bitrate = 500000\nfd = true");
  BenchConfigs configs = Combine(fd_station, kSequenceText, kLimitsText);
  // (The sequence loader already refuses more than any transport carries; the check is the
  // second line, for configs built in code.)
  configs.sequence.runs[0].sample_rate_hz = 12000;
  auto result = CheckBenchConfigs(configs);
  ASSERT_FALSE(result.has_value());
  EXPECT_EQ(result.error().key, "runs[0].sample_rate_hz");
  EXPECT_EQ(result.error().value, "12000");
  EXPECT_NE(result.error().message.find("CAN FD carries at most 10000 samples/s"),
            std::string::npos)
      << result.error().ToString();
}

// The simulated electronics report the resonant frequency in a 24-bit mHz field; a station that
// asks for more is refused when it is loaded, naming the line, not when the first run starts.
TEST(MalformedConfigs, SimulatedResonantFrequencyBeyondTheProtocolsField) {
  std::ifstream in(std::string(HRGBENCH_SOURCE_DIR) + "/bench_configs/station-sim.toml");
  std::stringstream text;
  text << in.rdbuf();
  const std::string station =
      Mutate(text.str(), "resonant_frequency_hz = 5000.0", "resonant_frequency_hz = 20000.0");
  auto result = ParseStationConfig(station, "sim.toml");
  ASSERT_FALSE(result.has_value());
  EXPECT_EQ(result.error().file, "sim.toml");
  EXPECT_EQ(result.error().line, LineOfText(station, "resonant_frequency_hz = 20000.0"));
  EXPECT_EQ(result.error().key, "simulated.resonant_frequency_hz");
  EXPECT_NE(result.error().message.find("16777.215"), std::string::npos)
      << result.error().ToString();
}

TEST(CrossChecks, LimitOnAParameterTheSequenceCannotDetermine) {
  // One rate only (Earth rate added to both runs alike): ξ is not identifiable.
  const std::string sequence = Mutate(kSequenceText, "omega_rad_s = -0.5", "omega_rad_s = 0.5");
  auto result = CheckBenchConfigs(Combine(kStationText, sequence, kLimitsText));
  ASSERT_FALSE(result.has_value());
  EXPECT_EQ(result.error().file, "l.toml");
  EXPECT_EQ(result.error().line, 4u);
  EXPECT_EQ(result.error().key, "limits.xi1");
  EXPECT_NE(result.error().message.find("does not determine it"), std::string::npos)
      << result.error().ToString();
}

}  // namespace
}  // namespace hrgbench::bench
