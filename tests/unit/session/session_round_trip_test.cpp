// Writing a session and reading it back: unknown keys survive, typed fields win, statuses other
// than "complete" are skipped with a warning.

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "hrgbench/session/session.hpp"
#include "session_test_util.hpp"

namespace hrgbench::session {
namespace {

using nlohmann::json;
using testing::ExpectError;
using testing::ReadText;
using testing::ReferenceDir;
using testing::TempDir;
using testing::WriteText;

void ExpectSameSamples(const RunSamples& actual, const RunSamples& expected) {
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k) {
    ASSERT_EQ(std::bit_cast<std::uint64_t>(actual.t_s[k]),
              std::bit_cast<std::uint64_t>(expected.t_s[k]));
  }
  for (Eigen::Index i = 0; i < expected.y.size(); ++i) {
    ASSERT_EQ(std::bit_cast<std::uint64_t>(actual.y.data()[i]),
              std::bit_cast<std::uint64_t>(expected.y.data()[i]));
  }
}

RunSamples TwoSamples() {
  RunSamples samples;
  samples.t_s = {0.0, 0.01};
  samples.y = Eigen::Matrix4Xd::Constant(4, 2, 0.25);
  return samples;
}

TEST(SessionRoundTripTest, ReferenceSessionSurvivesWriteAndRead) {
  for (const char* name : {"paper-noisefree", "ratetable-noisefree"}) {
    SCOPED_TRACE(name);
    const auto original = ReadSession(ReferenceDir(name));
    ASSERT_TRUE(original) << original.error().ToString();
    TempDir dir;
    ASSERT_TRUE(WriteSessionJson(dir.path(), *original));
    for (std::size_t i = 0; i < original->loaded_run_ids.size(); ++i) {
      const auto written = WriteRunCsv(dir / original->runs[i].file, original->loaded_samples[i]);
      ASSERT_TRUE(written) << written.error().ToString();
    }
    const auto copy = ReadSession(dir.path());
    ASSERT_TRUE(copy) << copy.error().ToString();
    ASSERT_TRUE(copy->document.contains("simulation"));
    EXPECT_EQ(copy->document["simulation"], original->document["simulation"]);
    // The copy states the I/Q convention the reader assumed for the older original (the writer
    // always records it); everything else is as it was.
    EXPECT_EQ(copy->document["electronics"]["iq_convention"], "minus-sine");
    EXPECT_TRUE(copy->notes.empty());
    nlohmann::json stated = original->document;
    stated["electronics"]["iq_convention"] = "minus-sine";
    EXPECT_EQ(copy->document, stated);
    EXPECT_EQ(copy->serial, original->serial);
    EXPECT_EQ(copy->sample_rate_hz, original->sample_rate_hz);
    ASSERT_EQ(copy->runs.size(), original->runs.size());
    ASSERT_EQ(copy->loaded_samples.size(), original->loaded_samples.size());
    for (std::size_t i = 0; i < copy->runs.size(); ++i) {
      EXPECT_EQ(copy->runs[i].id, original->runs[i].id);
      EXPECT_EQ(std::bit_cast<std::uint64_t>(copy->runs[i].omega_rad_s),
                std::bit_cast<std::uint64_t>(original->runs[i].omega_rad_s));
      ExpectSameSamples(copy->loaded_samples[i], original->loaded_samples[i]);
    }
  }
}

TEST(SessionRoundTripTest, TypedFieldsWinAndUnknownKeysSurviveInsideRuns) {
  TempDir dir;
  Session session;
  session.document = json::parse(R"({
    "format": "old", "version": 0, "unit": {"serial": "stale", "model": "HRG-30"},
    "station": {"name": "bench-2"},
    "runs": [{"id": 2, "file": "x.csv", "omega_rad_s": 9, "status": "aborted",
              "started_at": "2024-05-01T10:00:00Z"}]})");
  session.serial = "SN-0042";
  session.sample_rate_hz = 250.0;
  session.runs = {{1, "runs/run-001.csv", -1e-4, "complete"},
                  {2, "runs/run-002.csv", 1e-4, "complete"}};
  ASSERT_TRUE(WriteSessionJson(dir.path(), session));
  ASSERT_TRUE(WriteRunCsv(dir / "runs/run-001.csv", TwoSamples()));
  ASSERT_TRUE(WriteRunCsv(dir / "runs/run-002.csv", TwoSamples()));

  const auto read = ReadSession(dir.path());
  ASSERT_TRUE(read) << read.error().ToString();
  EXPECT_EQ(read->serial, "SN-0042");
  EXPECT_EQ(read->sample_rate_hz, 250.0);
  EXPECT_EQ(read->document["format"], kFormatName);
  EXPECT_EQ(read->document["version"], kFormatVersion);
  EXPECT_EQ(read->document["unit"]["model"], "HRG-30");
  EXPECT_EQ(read->document["station"]["name"], "bench-2");
  ASSERT_EQ(read->runs.size(), 2u);
  EXPECT_EQ(read->runs[1].file, "runs/run-002.csv");
  EXPECT_EQ(read->runs[1].status, "complete");
  EXPECT_EQ(read->document["runs"][1]["started_at"], "2024-05-01T10:00:00Z");
  EXPECT_FALSE(read->document["runs"][0].contains("started_at"));
  EXPECT_EQ(read->loaded_run_ids, (std::vector<int>{1, 2}));
}

TEST(SessionRoundTripTest, NonCompleteRunsAreSkippedWithWarning) {
  TempDir dir;
  Session session;
  session.serial = "SN-1";
  session.sample_rate_hz = 100.0;
  // Run 2 was aborted and never got a CSV: that must not be an error.
  session.runs = {{1, "runs/run-001.csv", -1e-4, "complete"},
                  {2, "runs/run-002.csv", 0.0, "aborted"},
                  {3, "runs/run-003.csv", 1e-4, "complete"},
                  {4, "runs/run-004.csv", 2e-4, "error"}};
  ASSERT_TRUE(WriteSessionJson(dir.path(), session));
  ASSERT_TRUE(WriteRunCsv(dir / "runs/run-001.csv", TwoSamples()));
  ASSERT_TRUE(WriteRunCsv(dir / "runs/run-003.csv", TwoSamples()));

  const auto read = ReadSession(dir.path());
  ASSERT_TRUE(read) << read.error().ToString();
  EXPECT_EQ(read->runs.size(), 4u);
  EXPECT_EQ(read->loaded_run_ids, (std::vector<int>{1, 3}));
  EXPECT_EQ(read->loaded_samples.size(), 2u);
  EXPECT_EQ(read->warnings, (std::vector<std::string>{"run 2 skipped: status 'aborted'",
                                                      "run 4 skipped: status 'error'"}));
  const auto runs = ToRunData(*read);
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[1].id, 3);
  EXPECT_EQ(runs[1].omega_rad_s, 1e-4);
}

TEST(SessionRoundTripTest, WriterRefusesWhatTheReaderWouldReject) {
  TempDir dir;
  const auto file = dir / "session.json";
  Session good;
  good.serial = "SN-1";
  good.sample_rate_hz = 100.0;
  good.runs = {{1, "runs/run-001.csv", 0.0, "complete"}, {2, "runs/run-002.csv", 0.0, "complete"}};

  Session s = good;
  s.runs[1].id = 1;
  ExpectError(WriteSessionJson(dir.path(), s).error(), file, 0, "runs[1].id", "duplicate run id 1");
  s = good;
  s.runs[0].id = 0;
  ExpectError(WriteSessionJson(dir.path(), s).error(), file, 0, "runs[0].id", ">= 1, got 0");
  s = good;
  s.runs[1].file = "../elsewhere.csv";
  ExpectError(WriteSessionJson(dir.path(), s).error(), file, 0, "runs[1].file",
              "'../elsewhere.csv' is outside the session directory");
  s = good;
  s.runs[0].omega_rad_s = HUGE_VAL;
  ExpectError(WriteSessionJson(dir.path(), s).error(), file, 0, "runs[0].omega_rad_s",
              "non-finite");
  s = good;
  s.sample_rate_hz = 0.0;
  ExpectError(WriteSessionJson(dir.path(), s).error(), file, 0, "sample_rate_hz", "positive");
  s = good;
  s.document = json::array();
  ExpectError(WriteSessionJson(dir.path(), s).error(), file, 0, "", "got array");
  s = good;
  s.serial = "\xff\xfe";
  ExpectError(WriteSessionJson(dir.path(), s).error(), file, 0, "", "UTF-8");
  EXPECT_FALSE(std::filesystem::exists(file));

  ASSERT_TRUE(WriteSessionJson(dir.path(), good));
  EXPECT_NE(ReadText(file).find("\"format\": \"hrgbench-session\""), std::string::npos);
}

}  // namespace
}  // namespace hrgbench::session
