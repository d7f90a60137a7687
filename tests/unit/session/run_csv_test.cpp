// Run CSV: exact round trips, column handling, accepted variants, writer refusals, parse speed.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "hrgbench/session/session.hpp"
#include "session_test_util.hpp"

namespace hrgbench::session {
namespace {

using testing::ExpectError;
using testing::ReadText;
using testing::TempDir;
using testing::WriteText;

std::uint64_t Bits(double value) { return std::bit_cast<std::uint64_t>(value); }

// Any finite double, drawn uniformly over bit patterns (so all exponents, subnormals, signs).
double RandomFiniteDouble(std::mt19937_64& rng) {
  for (;;) {
    const double value = std::bit_cast<double>(rng());
    if (std::isfinite(value)) return value;
  }
}

RunSamples RandomSamples(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  RunSamples samples;
  samples.t_s.resize(n);
  for (double& t : samples.t_s) t = RandomFiniteDouble(rng);
  std::sort(samples.t_s.begin(), samples.t_s.end());
  samples.t_s.erase(std::unique(samples.t_s.begin(), samples.t_s.end()), samples.t_s.end());
  n = samples.t_s.size();
  samples.y.resize(4, static_cast<Eigen::Index>(n));
  for (Eigen::Index k = 0; k < samples.y.size(); ++k) samples.y.data()[k] = RandomFiniteDouble(rng);
  // The awkward values, placed where they will be read back.
  const double specials[] = {-0.0,
                             0.1,
                             1.0 / 3.0,
                             std::numeric_limits<double>::denorm_min(),
                             std::numeric_limits<double>::min(),
                             std::numeric_limits<double>::max(),
                             std::numeric_limits<double>::lowest(),
                             -std::numeric_limits<double>::epsilon(),
                             5.000000000000001e-05,
                             1e23};
  for (std::size_t i = 0; i < std::size(specials); ++i) samples.y.data()[i] = specials[i];
  for (const char* name : {"seq", "omega_meas_rad_s", "temp_c"}) {
    auto& column = samples.extra_columns[name];
    column.resize(n);
    for (double& v : column) v = RandomFiniteDouble(rng);
  }
  return samples;
}

void ExpectBitExact(const RunSamples& actual, const RunSamples& expected) {
  ASSERT_EQ(actual.size(), expected.size());
  ASSERT_EQ(actual.y.cols(), expected.y.cols());
  for (std::size_t k = 0; k < expected.size(); ++k) {
    ASSERT_EQ(Bits(actual.t_s[k]), Bits(expected.t_s[k])) << "t_s[" << k << "]";
  }
  for (Eigen::Index i = 0; i < expected.y.size(); ++i) {
    ASSERT_EQ(Bits(actual.y.data()[i]), Bits(expected.y.data()[i])) << "y element " << i;
  }
  ASSERT_EQ(actual.extra_columns.size(), expected.extra_columns.size());
  for (const auto& [name, values] : expected.extra_columns) {
    const auto it = actual.extra_columns.find(name);
    ASSERT_NE(it, actual.extra_columns.end()) << name;
    ASSERT_EQ(it->second.size(), values.size()) << name;
    for (std::size_t k = 0; k < values.size(); ++k) {
      ASSERT_EQ(Bits(it->second[k]), Bits(values[k])) << name << "[" << k << "]";
    }
  }
}

TEST(RunCsvTest, RandomDoublesRoundTripBitExact) {
  TempDir dir;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const RunSamples original = RandomSamples(2000, seed);
    const auto file = dir / "deep/er/runs/run-001.csv";  // parent directories do not exist yet
    const auto written = WriteRunCsv(file, original);
    ASSERT_TRUE(written) << written.error().ToString();
    const auto read = ReadRunCsv(file);
    ASSERT_TRUE(read) << read.error().ToString();
    ExpectBitExact(*read, original);
  }
}

TEST(RunCsvTest, WriterPutsExtraColumnsAfterYInNameOrderWithShortestValues) {
  TempDir dir;
  RunSamples samples;
  samples.t_s = {0.0, 0.01};
  samples.y.resize(4, 2);
  samples.y << 1.01, 0.5, 0.0, -0.0, 1e-300, 2.0, -0.396, 0.1;
  samples.extra_columns["temp_c"] = {25.5, 25.25};
  samples.extra_columns["seq"] = {7, 8};
  const auto file = dir / "run.csv";
  ASSERT_TRUE(WriteRunCsv(file, samples));
  EXPECT_EQ(ReadText(file),
            "t_s,y1,y2,y3,y4,seq,temp_c\n"
            "0,1.01,0,1e-300,-0.396,7,25.5\n"
            "0.01,0.5,-0,2,0.1,8,25.25\n");
}

TEST(RunCsvTest, ReadsColumnsInAnyOrderWithExtraColumns) {
  TempDir dir;
  const auto file = dir / "run.csv";
  WriteText(file,
            "seq,y3,temp_c,t_s,y1,omega_meas_rad_s,y4,y2\n"
            "1,0.3,20.5,0.0,0.1,-1e-4,0.4,0.2\n"
            "2,1.3,20.75,0.01,1.1,-2e-4,1.4,1.2\n");
  const auto read = ReadRunCsv(file);
  ASSERT_TRUE(read) << read.error().ToString();
  ASSERT_EQ(read->size(), 2u);
  EXPECT_EQ(read->t_s, (std::vector<double>{0.0, 0.01}));
  Eigen::Matrix4Xd expected_y(4, 2);
  expected_y << 0.1, 1.1, 0.2, 1.2, 0.3, 1.3, 0.4, 1.4;
  EXPECT_TRUE(read->y == expected_y) << read->y;
  ASSERT_EQ(read->extra_columns.size(), 3u);
  EXPECT_EQ(read->extra_columns.at("seq"), (std::vector<double>{1, 2}));
  EXPECT_EQ(read->extra_columns.at("temp_c"), (std::vector<double>{20.5, 20.75}));
  EXPECT_EQ(read->extra_columns.at("omega_meas_rad_s"), (std::vector<double>{-1e-4, -2e-4}));
}

TEST(RunCsvTest, AcceptsCrLfMissingFinalNewlineAndBom) {
  TempDir dir;
  const auto file = dir / "run.csv";
  WriteText(file, "\xEF\xBB\xBFt_s,y1,y2,y3,y4\r\n0,1,2,3,4\r\n0.5,5,6,7,8");
  const auto read = ReadRunCsv(file);
  ASSERT_TRUE(read) << read.error().ToString();
  ASSERT_EQ(read->size(), 2u);
  EXPECT_EQ(read->t_s[1], 0.5);
  EXPECT_EQ(read->y(3, 1), 8.0);
}

TEST(RunCsvTest, WriterRefusesWhatTheReaderWouldReject) {
  TempDir dir;
  const auto file = dir / "run.csv";
  RunSamples good;
  good.t_s = {0.0, 0.01, 0.02};
  good.y = Eigen::Matrix4Xd::Zero(4, 3);

  RunSamples nan_y = good;
  nan_y.y(1, 2) = std::nan("");
  ExpectError(WriteRunCsv(file, nan_y).error(), file, 4, "y2", "non-finite value nan");

  RunSamples flat_time = good;
  flat_time.t_s[2] = 0.01;
  ExpectError(WriteRunCsv(file, flat_time).error(), file, 4, "t_s", "0.01 after 0.01");

  RunSamples short_y = good;
  short_y.y.resize(4, 2);
  ExpectError(WriteRunCsv(file, short_y).error(), file, 0, "y", "2 samples, t_s has 3");

  RunSamples bad_name = good;
  bad_name.extra_columns["a,b"] = {1, 2, 3};
  ExpectError(WriteRunCsv(file, bad_name).error(), file, 0, "a,b", "invalid column name");

  RunSamples repeated = good;
  repeated.extra_columns["y1"] = {1, 2, 3};
  ExpectError(WriteRunCsv(file, repeated).error(), file, 0, "y1", "repeats a required column");

  RunSamples short_extra = good;
  short_extra.extra_columns["temp_c"] = {1, 2};
  ExpectError(WriteRunCsv(file, short_extra).error(), file, 0, "temp_c", "2 values, t_s has 3");

  RunSamples inf_extra = good;
  inf_extra.extra_columns["temp_c"] = {1, -HUGE_VAL, 3};
  ExpectError(WriteRunCsv(file, inf_extra).error(), file, 3, "temp_c", "non-finite value -inf");

  EXPECT_FALSE(std::filesystem::exists(file)) << "a refused write must not create the file";
}

TEST(RunCsvTest, OverwriteLeavesNoTemporaryBehind) {
  TempDir dir;
  const auto file = dir / "runs/run-001.csv";
  RunSamples samples = RandomSamples(10, 7);
  ASSERT_TRUE(WriteRunCsv(file, samples));
  samples.t_s.back() = std::nextafter(samples.t_s.back(), HUGE_VAL);
  ASSERT_TRUE(WriteRunCsv(file, samples));
  const auto read = ReadRunCsv(file);
  ASSERT_TRUE(read) << read.error().ToString();
  ExpectBitExact(*read, samples);
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(file.parent_path())) {
    names.push_back(entry.path().filename().string());
  }
  EXPECT_EQ(names, std::vector<std::string>{"run-001.csv"});
}

TEST(RunCsvTest, WriteFileAtomicReportsUnwritableDirectory) {
  TempDir dir;
  WriteText(dir / "plain-file", "x");
  const auto target = dir / "plain-file/inside.txt";
  const auto result = WriteFileAtomic(target, "hello");
  ASSERT_FALSE(result);
  ExpectError(result.error(), target, 0, "", "cannot create temporary");
}

// 100 000 lines of typical capture data (t, four channels at 17 significant digits, a sequence
// number) come back bit for bit. (How fast: benchmarks/, not here: a test never judges speed.)
TEST(RunCsvTest, Reads100kLinesBackBitForBit) {
  TempDir dir;
  constexpr std::size_t kLines = 100'000;
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> channel(-1.0, 1.0);
  RunSamples samples;
  samples.t_s.resize(kLines);
  samples.y.resize(4, kLines);
  auto& seq = samples.extra_columns["seq"];
  seq.resize(kLines);
  for (std::size_t k = 0; k < kLines; ++k) {
    samples.t_s[k] = static_cast<double>(k) / 100.0;
    seq[k] = static_cast<double>(k);
    for (int c = 0; c < 4; ++c) samples.y(c, static_cast<Eigen::Index>(k)) = channel(rng);
  }
  const auto file = dir / "big.csv";
  ASSERT_TRUE(WriteRunCsv(file, samples));
  const auto read = ReadRunCsv(file);
  ASSERT_TRUE(read) << read.error().ToString();
  ASSERT_EQ(read->size(), kLines);
  EXPECT_EQ(read->t_s, samples.t_s);
  EXPECT_TRUE(read->y == samples.y);
  EXPECT_EQ(read->extra_columns.at("seq"), seq);
}

}  // namespace
}  // namespace hrgbench::session
