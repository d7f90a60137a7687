// The three reference sessions, written by an independent Python prototype, read as the estimator
// will read them. Expected values come from the files' own text, parsed here with strtod.

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "hrgbench/session/session.hpp"
#include "session_test_util.hpp"

namespace hrgbench::session {
namespace {

using testing::ReadText;
using testing::ReferenceDir;

struct ReferenceCase {
  std::string name;
  std::vector<double> omega_rad_s;  // as printed in session.json
  std::size_t samples_per_run;
  std::string serial;
};

// The prototype samples t = k / fs for k < T * fs: 10 s at 100 Hz is 1000 samples (1001 lines with
// the header), 20 s is 2000.
const ReferenceCase kCases[] = {
    {"paper-noisefree",
     {-0.0001, -5e-05, 0.0, 5.000000000000001e-05, 0.0001},
     1000,
     "REF-paper-noisefree"},
    {"paper-sigma1e-4",
     {-0.0001, -5e-05, 0.0, 5.000000000000001e-05, 0.0001},
     1000,
     "REF-paper-sigma1e-4"},
    {"ratetable-noisefree", {0.1, -0.1, 0.3, -0.3, 1.0, -1.0}, 2000, "REF-ratetable-noisefree"},
};

// gtest would otherwise print the struct's bytes in every test name.
void PrintTo(const ReferenceCase& c, std::ostream* os) { *os << c.name; }

// Line `index` (0-based, 0 = header) of a CSV, split on commas and parsed with strtod.
std::vector<double> CsvLineValues(const std::filesystem::path& file, std::size_t index) {
  std::istringstream in(ReadText(file));
  std::string line;
  for (std::size_t i = 0; i <= index; ++i) std::getline(in, line);
  std::vector<double> values;
  std::istringstream fields(line);
  for (std::string field; std::getline(fields, field, ',');) {
    values.push_back(std::strtod(field.c_str(), nullptr));
  }
  return values;
}

void ExpectBitEqual(double actual, double expected, const std::string& what) {
  EXPECT_EQ(std::bit_cast<std::uint64_t>(actual), std::bit_cast<std::uint64_t>(expected))
      << what << ": " << actual << " vs " << expected;
}

class ReferenceSessionTest : public ::testing::TestWithParam<ReferenceCase> {};

TEST_P(ReferenceSessionTest, ReadsRunsOmegaAndSamples) {
  const ReferenceCase& c = GetParam();
  const auto dir = ReferenceDir(c.name);
  const auto session = ReadSession(dir);
  ASSERT_TRUE(session) << session.error().ToString();

  EXPECT_EQ(session->serial, c.serial);
  EXPECT_EQ(session->sample_rate_hz, 100.0);
  EXPECT_TRUE(session->warnings.empty());
  EXPECT_TRUE(session->document.contains("simulation"));
  ASSERT_EQ(session->runs.size(), c.omega_rad_s.size());
  ASSERT_EQ(session->loaded_run_ids.size(), c.omega_rad_s.size());
  ASSERT_EQ(session->loaded_samples.size(), c.omega_rad_s.size());
  for (std::size_t i = 0; i < c.omega_rad_s.size(); ++i) {
    SCOPED_TRACE("run index " + std::to_string(i));
    const RunEntry& run = session->runs[i];
    EXPECT_EQ(run.id, static_cast<int>(i + 1));
    EXPECT_EQ(session->loaded_run_ids[i], static_cast<int>(i + 1));
    ExpectBitEqual(run.omega_rad_s, c.omega_rad_s[i], "omega");
    EXPECT_EQ(run.status, "complete");
    char expected_file[64];
    std::snprintf(expected_file, sizeof(expected_file), "runs/run-%03zu.csv", i + 1);
    EXPECT_EQ(run.file, expected_file);

    const RunSamples& samples = session->loaded_samples[i];
    ASSERT_EQ(samples.size(), c.samples_per_run);
    ASSERT_EQ(static_cast<std::size_t>(samples.y.cols()), c.samples_per_run);
    EXPECT_TRUE(samples.extra_columns.empty());

    const auto csv = dir / run.file;
    const std::vector<double> first = CsvLineValues(csv, 1);
    ASSERT_EQ(first.size(), 5u);
    ExpectBitEqual(samples.t_s[0], first[0], "first t_s");
    for (int channel = 0; channel < 4; ++channel) {
      ExpectBitEqual(samples.y(channel, 0), first[static_cast<std::size_t>(channel) + 1],
                     "first y" + std::to_string(channel + 1));
    }
    const std::vector<double> last = CsvLineValues(csv, c.samples_per_run);
    const auto k = static_cast<Eigen::Index>(c.samples_per_run - 1);
    ExpectBitEqual(samples.t_s.back(), last[0], "last t_s");
    for (int channel = 0; channel < 4; ++channel) {
      ExpectBitEqual(samples.y(channel, k), last[static_cast<std::size_t>(channel) + 1],
                     "last y" + std::to_string(channel + 1));
    }
  }
}

TEST_P(ReferenceSessionTest, ToRunDataCarriesIdOmegaAndSamples) {
  const ReferenceCase& c = GetParam();
  const auto session = ReadSession(ReferenceDir(c.name));
  ASSERT_TRUE(session) << session.error().ToString();
  const auto runs = ToRunData(*session);
  ASSERT_EQ(runs.size(), c.omega_rad_s.size());
  for (std::size_t i = 0; i < runs.size(); ++i) {
    EXPECT_EQ(runs[i].id, static_cast<int>(i + 1));
    ExpectBitEqual(runs[i].omega_rad_s, c.omega_rad_s[i], "omega");
    EXPECT_EQ(runs[i].t_s, session->loaded_samples[i].t_s);
    EXPECT_EQ(runs[i].size(), static_cast<Eigen::Index>(c.samples_per_run));
    EXPECT_TRUE(runs[i].y == session->loaded_samples[i].y);
  }
}

TEST_P(ReferenceSessionTest, JsonOnlyReadLoadsNoSamples) {
  ReadOptions options;
  options.load_samples = false;
  const auto session = ReadSession(ReferenceDir(GetParam().name), options);
  ASSERT_TRUE(session) << session.error().ToString();
  EXPECT_EQ(session->runs.size(), GetParam().omega_rad_s.size());
  EXPECT_TRUE(session->loaded_run_ids.empty());
  EXPECT_TRUE(session->loaded_samples.empty());
}

INSTANTIATE_TEST_SUITE_P(Reference, ReferenceSessionTest, ::testing::ValuesIn(kCases),
                         [](const auto& test_info) {
                           std::string name = test_info.param.name;
                           for (char& ch : name) {
                             if (ch == '-') ch = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace hrgbench::session
