// The station's [gyro] output_filter keys (the electronics' low-pass that shapes the pick-off
// noise, output_filter.hpp): defaults, the values loaded, bad values named by file, key and value,
// and the cross-check against the sequence's sample rates.

#include <gtest/gtest.h>

#include <string>

#include "hand_made_record.hpp"
#include "hrgbench/analysis/output_filter.hpp"
#include "hrgbench/config/bench_configs.hpp"
#include "hrgbench/config/sequence_config.hpp"
#include "hrgbench/config/station_config.hpp"
#include "hrgbench/estimator/noise_shape.hpp"

namespace hrgbench::bench {
namespace {

using testing::RecordOf;

std::string Station(const std::string& gyro_keys) {
  return "[station]\nname = \"x\"\nkind = \"simulated\"\n[site]\nlatitude_deg = 45.0\n"
         "axis_enu = [0.0, 0.0, 1.0]\n[gyro]\n" +
         gyro_keys + "[simulated]\n";
}

TEST(StationOutputFilter, AbsentMeansNoFilter) {
  auto station = ParseStationConfig(Station(""), "s.toml");
  ASSERT_TRUE(station.has_value()) << station.error().ToString();
  EXPECT_EQ(station->gyro.output_filter.kind, OutputFilterKind::kNone);
  EXPECT_EQ(OutputFilterJson(station->gyro.output_filter), nlohmann::json({{"kind", "none"}}));
}

TEST(StationOutputFilter, ButterworthIsLoadedWithItsOrderAndCutoff) {
  auto station =
      ParseStationConfig(Station("output_filter = \"butterworth\"\noutput_filter_order = 6\n"
                                 "output_filter_cutoff_hz = 150.0\n"),
                         "s.toml");
  ASSERT_TRUE(station.has_value()) << station.error().ToString();
  const OutputFilter& filter = station->gyro.output_filter;
  EXPECT_EQ(filter.kind, OutputFilterKind::kButterworth);
  EXPECT_EQ(filter.order, 6);
  EXPECT_EQ(filter.cutoff_hz, 150.0);
  // The shape at 1 kHz: a Butterworth's noise, correlated at lag 1 (a 150 Hz filter at 1 kHz
  // passes 0.3 of the Nyquist band: neighbouring samples are strongly alike).
  auto shape = NoiseShapeOf(filter, 1000.0);
  ASSERT_TRUE(shape.has_value()) << shape.error();
  EXPECT_FALSE(shape->IsWhite());
  EXPECT_GT(shape->Rho(1), 0.3);
  // The record's form reads back to the same shape.
  nlohmann::json doc = {{"electronics", {{"output_filter", OutputFilterJson(filter)}}}};
  auto recorded = RecordedNoiseShape(RecordOf(doc).electronics, 1000.0);
  ASSERT_TRUE(recorded.has_value()) << recorded.error();
  EXPECT_EQ(recorded->autocorrelation, shape->autocorrelation);
}

TEST(StationOutputFilter, BadValuesNameTheKeyAndValue) {
  struct Case {
    std::string keys;
    std::string key;
    std::string value;
  };
  const Case cases[] = {
      {"output_filter = \"bessel\"\n", "gyro.output_filter", "\"bessel\""},
      {"output_filter = \"butterworth\"\noutput_filter_order = 13\n", "gyro.output_filter_order",
       "13"},
      {"output_filter = \"butterworth\"\noutput_filter_order = 0\n", "gyro.output_filter_order",
       "0"},
      {"output_filter = \"butterworth\"\noutput_filter_cutoff_hz = 0.0\n",
       "gyro.output_filter_cutoff_hz", "0.0"},
      {"output_filter = \"butterworth\"\noutput_filter_cutoff_hz = -5.0\n",
       "gyro.output_filter_cutoff_hz", "-5.0"},
      // Order and cutoff without a filter would silently declare nothing.
      {"output_filter_cutoff_hz = 200.0\n", "gyro.output_filter_cutoff_hz", "200.0"},
      {"output_filter = \"none\"\noutput_filter_order = 4\n", "gyro.output_filter_order", "4"},
  };
  for (const Case& c : cases) {
    auto station = ParseStationConfig(Station(c.keys), "s.toml");
    ASSERT_FALSE(station.has_value()) << c.keys;
    EXPECT_EQ(station.error().file, "s.toml");
    EXPECT_EQ(station.error().key, c.key) << station.error().ToString();
    EXPECT_EQ(station.error().value, c.value) << station.error().ToString();
    EXPECT_GT(station.error().line, 0u) << station.error().ToString();
  }
}

TEST(StationIqConvention, DefaultIsTheModelsAndPlusSineIsLoaded) {
  // [gyro] iq_convention (estimator/iq_convention.hpp): absent = the model's "minus-sine".
  auto absent = ParseStationConfig(Station(""), "s.toml");
  ASSERT_TRUE(absent.has_value()) << absent.error().ToString();
  EXPECT_EQ(absent->gyro.iq_convention, estimator::IqConvention::kMinusSine);
  auto plus = ParseStationConfig(Station("iq_convention = \"plus-sine\"\n"), "s.toml");
  ASSERT_TRUE(plus.has_value()) << plus.error().ToString();
  EXPECT_EQ(plus->gyro.iq_convention, estimator::IqConvention::kPlusSine);
  auto bad = ParseStationConfig(Station("iq_convention = \"plus-cosine\"\n"), "s.toml");
  ASSERT_FALSE(bad.has_value());
  EXPECT_EQ(bad.error().file, "s.toml");
  EXPECT_EQ(bad.error().key, "gyro.iq_convention") << bad.error().ToString();
  EXPECT_EQ(bad.error().value, "\"plus-cosine\"") << bad.error().ToString();
  EXPECT_GT(bad.error().line, 0u);
}

BenchConfigs WithFilter(double cutoff_hz) {
  BenchConfigs configs;
  auto station =
      ParseStationConfig(Station("output_filter = \"butterworth\"\noutput_filter_cutoff_hz = " +
                                 std::to_string(cutoff_hz) + "\n"),
                         "s.toml");
  EXPECT_TRUE(station.has_value()) << station.error().ToString();
  if (station) configs.station = *station;
  auto sequence = LoadSequenceConfig(std::string(HRGBENCH_SOURCE_DIR) +
                                     "/bench_configs/sequence-production.toml");
  EXPECT_TRUE(sequence.has_value()) << sequence.error().ToString();
  if (sequence) configs.sequence = *sequence;
  return configs;
}

// The carrier station's filter at the production rate. Independently (Simpson's rule on
// ∫cos(2πfτ)/(1 + (f/f_c)^8) df over [0, 60·f_c], 2e5 intervals): ρ1 = 0.7119, ρ6 = 0.037,
// ρ7 = 0.0206, ρ8 = −0.0042, ρ9 = −0.0100, ρ10 = −0.0033, |ρ| < 0.003 beyond: the memory is 8
// samples (|ρ9| = 0.00999 by the closed form).
TEST(StationOutputFilter, TheCarrierFiltersMemoryAtOneKilohertz) {
  OutputFilter filter;
  filter.kind = OutputFilterKind::kButterworth;
  auto shape = NoiseShapeOf(filter, 1000.0);
  ASSERT_TRUE(shape.has_value()) << shape.error();
  EXPECT_NEAR(shape->Rho(1), 0.7119, 1e-4);
  EXPECT_NEAR(shape->Rho(7), 0.0206, 1e-4);
  EXPECT_EQ(estimator::NoiseMemoryLags(*shape), 8);
}

TEST(StationOutputFilter, TheShippedProductionSequenceFitsTheCarrierFilter) {
  const BenchConfigs configs = WithFilter(200.0);
  auto ok = CheckBenchConfigs(configs);
  EXPECT_TRUE(ok.has_value()) << ok.error().ToString();
}

TEST(StationOutputFilter, OneSampleRatePerSessionWithAFilter) {
  BenchConfigs configs = WithFilter(200.0);
  ASSERT_GE(configs.sequence.runs.size(), 2u);
  configs.sequence.runs[1].sample_rate_hz = 500;
  auto ok = CheckBenchConfigs(configs);
  ASSERT_FALSE(ok.has_value());
  EXPECT_EQ(ok.error().key, "runs[1].sample_rate_hz");
  EXPECT_EQ(ok.error().value, "500");
  EXPECT_NE(ok.error().message.find("output_filter"), std::string::npos) << ok.error().message;
}

TEST(StationOutputFilter, ACutoffTooLowForTheRateIsNamed) {
  // 0.01 Hz at 1 kHz: the slowest pole's envelope e^{−2π·0.01·sin(π/8)·k/1000} needs ~70 000
  // samples to fall below 0.01 — beyond the 4096 the estimator accepts.
  const BenchConfigs configs = WithFilter(0.01);
  auto ok = CheckBenchConfigs(configs);
  ASSERT_FALSE(ok.has_value());
  EXPECT_EQ(ok.error().file, "s.toml");
  EXPECT_EQ(ok.error().key, "gyro.output_filter_cutoff_hz");
  EXPECT_EQ(ok.error().value, "0.01");
  EXPECT_NE(ok.error().message.find("4096"), std::string::npos) << ok.error().message;
}

// What hrg-estimate and the sequencer read back (through the record's one reader): a damaged
// record names the field and its value.
TEST(StationOutputFilter, ADamagedRecordNamesTheFieldAndValue) {
  const nlohmann::json butterworth = {{"kind", "butterworth"}, {"order", 4}, {"cutoff_hz", 200.0}};
  EXPECT_TRUE(RecordedNoiseShape(
      RecordOf({{"electronics", {{"output_filter", butterworth}}}}).electronics, 1000.0));
  EXPECT_TRUE(RecordedNoiseShape(RecordOf(nlohmann::json::object()).electronics, 1000.0)
                  ->IsWhite());  // older records
  struct Case {
    nlohmann::json filter;
    std::string field;
    std::string value;  // as the message shows it
  };
  const Case cases[] = {
      {"butterworth", "electronics.output_filter", "\"butterworth\""},
      {{{"kind", "bessel"}}, "electronics.output_filter.kind", "'bessel'"},
      {{{"kind", "butterworth"}, {"order", 40}, {"cutoff_hz", 200.0}},
       "electronics.output_filter.order",
       "40"},
      {{{"kind", "butterworth"}, {"order", 4}, {"cutoff_hz", -1.0}},
       "electronics.output_filter.cutoff_hz",
       "-1.0"},
      {{{"kind", "butterworth"}, {"order", 4}}, "electronics.output_filter.cutoff_hz", "missing"},
  };
  for (const Case& c : cases) {
    const auto record = session::ReadSessionRecord(
        testing::CompleteSessionDocument({{"electronics", {{"output_filter", c.filter}}}}),
        "test/session.json");
    ASSERT_FALSE(record.has_value()) << c.filter.dump();
    const std::string text = record.error().ToString();
    EXPECT_EQ(record.error().field, c.field) << text;
    EXPECT_NE(text.find(c.value), std::string::npos) << text;
  }
}

}  // namespace
}  // namespace hrgbench::bench
