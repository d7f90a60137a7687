// The bounds on what a session may say (session.hpp): each is refused with an error naming the
// file, and the deep nesting that crashed hrg-estimate (signal 11 at 100 000 levels) is refused
// in-process before the recursive JSON parser sees it.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "hrgbench/session/session.hpp"
#include "session_test_util.hpp"

namespace hrgbench::session {
namespace {

using testing::ExpectError;
using testing::TempDir;
using testing::WriteText;

constexpr const char* kCsv = "t_s,y1,y2,y3,y4\n0,1,0,0,0\n0.01,1,0,0,0\n";

// session.json with `unit` (line 4) and `runs` (line 6) given as text.
std::string SessionJson(const std::string& unit, const std::string& runs) {
  return "{\n  \"format\": \"hrgbench-session\",\n  \"version\": 1,\n  \"unit\": " + unit +
         ",\n  \"sample_rate_hz\": 100.0,\n  \"runs\": " + runs + "\n}\n";
}

const std::string kUnit = R"({"serial": "SN-1"})";
const std::string kRuns =
    R"([{"id": 1, "file": "runs/run-001.csv", "omega_rad_s": 0.5, "status": "complete"}])";

std::string Nested(std::size_t depth) { return std::string(depth, '[') + std::string(depth, ']'); }

class SessionBoundsTest : public ::testing::Test {
 protected:
  void SetUp() override { WriteText(dir_ / "runs/run-001.csv", kCsv); }

  std::expected<Session, SessionError> ReadWith(const std::string& json_text) {
    WriteText(json_file(), json_text);
    return ReadSession(dir_.path());
  }

  std::filesystem::path json_file() const { return dir_ / "session.json"; }

  TempDir dir_;
};

TEST_F(SessionBoundsTest, TheBaseReads) {
  const auto session = ReadWith(SessionJson(kUnit, kRuns));
  ASSERT_TRUE(session) << session.error().ToString();
}

TEST_F(SessionBoundsTest, UnitNested100000DeepIsRefusedWithTheDepth) {
  const auto session = ReadWith(SessionJson(Nested(100'000), kRuns));
  ASSERT_FALSE(session);
  ExpectError(session.error(), json_file(), 4, "", "nested deeper than 64 levels");
  EXPECT_NE(session.error().message.find("level 65"), std::string::npos)
      << session.error().ToString();
}

TEST_F(SessionBoundsTest, RunsNested100000DeepIsRefusedWithTheDepth) {
  const auto session = ReadWith(SessionJson(kUnit, Nested(100'000)));
  ASSERT_FALSE(session);
  ExpectError(session.error(), json_file(), 6, "", "nested deeper than 64 levels");
}

TEST_F(SessionBoundsTest, DepthAtTheBoundReadsAndOneMoreIsRefused) {
  // The root object is level 1, so an extra key may nest 63 levels.
  std::string text = SessionJson(kUnit, kRuns);
  text.insert(2, "\"extra\": " + Nested(kMaxSessionJsonDepth - 1) + ",");
  const auto at_bound = ReadWith(text);
  EXPECT_TRUE(at_bound) << at_bound.error().ToString();
  text = SessionJson(kUnit, kRuns);
  text.insert(2, "\"extra\": " + Nested(kMaxSessionJsonDepth) + ",");
  const auto beyond = ReadWith(text);
  ASSERT_FALSE(beyond);
  ExpectError(beyond.error(), json_file(), 2, "", "level 65");
}

TEST_F(SessionBoundsTest, BracketsInsideStringsAreNotNesting) {
  std::string text = SessionJson(kUnit, kRuns);
  text.insert(2, "\"note\": \"" + std::string(1000, '[') + "\\\"{{{\",");
  const auto session = ReadWith(text);
  EXPECT_TRUE(session) << session.error().ToString();
}

TEST_F(SessionBoundsTest, SerialWithANulIsRefused) {
  const auto session = ReadWith(SessionJson(R"({"serial": "SN\u0000-1"})", kRuns));
  ASSERT_FALSE(session);
  ExpectError(session.error(), json_file(), 4, "unit.serial", "control character U+0000 at byte 2");
}

TEST_F(SessionBoundsTest, OneMegabyteSerialIsRefused) {
  const auto session =
      ReadWith(SessionJson("{\"serial\": \"" + std::string(1 << 20, 'x') + "\"}", kRuns));
  ASSERT_FALSE(session);
  ExpectError(session.error(), json_file(), 4, "unit.serial", "1048576 bytes long (at most 255)");
}

TEST_F(SessionBoundsTest, StatusWithALineFeedIsRefused) {
  const auto session = ReadWith(SessionJson(
      kUnit,
      R"([{"id": 1, "file": "runs/run-001.csv", "omega_rad_s": 0.5, "status": "complete\nx"}])"));
  ASSERT_FALSE(session);
  ExpectError(session.error(), json_file(), 6, "runs[0].status", "control character U+000A");
}

TEST_F(SessionBoundsTest, MoreThanTheMaximumRunsIsRefused) {
  std::string runs = "[";
  for (std::size_t i = 1; i <= kMaxSessionRuns + 1; ++i) {
    runs += (i > 1 ? "," : "") + std::string("{\"id\": ") + std::to_string(i) +
            ", \"file\": \"runs/run-001.csv\", \"omega_rad_s\": 0.5, \"status\": \"aborted\"}";
  }
  const auto session = ReadWith(SessionJson(kUnit, runs + "]"));
  ASSERT_FALSE(session);
  ExpectError(session.error(), json_file(), 6, "runs", "1001 runs (at most 1000)");
}

TEST_F(SessionBoundsTest, SessionJsonThatIsADirectoryIsNamed) {
  std::filesystem::create_directories(json_file());
  const auto session = ReadSession(dir_.path());
  ASSERT_FALSE(session);
  ExpectError(session.error(), json_file(), 0, "", "is a directory, not a file");
}

TEST_F(SessionBoundsTest, SessionDirectoryThatIsAFileIsNamed) {
  WriteText(dir_ / "plain", "x");
  const auto session = ReadSession(dir_ / "plain");
  ASSERT_FALSE(session);
  ExpectError(session.error(), dir_ / "plain", 0, "", "not a directory");
}

TEST_F(SessionBoundsTest, OversizedSessionJsonIsRefusedUnread) {
  // Sparse: 64 MiB + 1 byte of zeros without writing them.
  WriteText(json_file(), "");
  std::filesystem::resize_file(json_file(), kMaxSessionJsonBytes + 1);
  const auto session = ReadSession(dir_.path());
  ASSERT_FALSE(session);
  ExpectError(session.error(), json_file(), 0, "", "file too large: 67108865 bytes");
}

TEST_F(SessionBoundsTest, WriterRefusesWhatTheReaderRefuses) {
  Session session;
  session.serial = std::string("SN\0-1", 5);
  session.sample_rate_hz = 100.0;
  auto written = WriteSessionJson(dir_ / "w", session);
  ASSERT_FALSE(written);
  EXPECT_EQ(written.error().field, "unit.serial");
  session.serial = "SN-1";
  session.document = nlohmann::json::object();
  nlohmann::json deep = nlohmann::json::array();
  for (std::size_t i = 0; i < kMaxSessionJsonDepth; ++i) deep = nlohmann::json::array({deep});
  session.document["extra"] = deep;
  written = WriteSessionJson(dir_ / "w", session);
  ASSERT_FALSE(written);
  EXPECT_NE(written.error().message.find("nested deeper than 64"), std::string::npos)
      << written.error().ToString();
}

// Run CSV bounds.
class RunCsvBoundsTest : public ::testing::Test {
 protected:
  std::filesystem::path csv() const { return dir_ / "run.csv"; }
  TempDir dir_;
};

TEST_F(RunCsvBoundsTest, TooManyColumnsIsRefused) {
  std::string header = "t_s,y1,y2,y3,y4";
  for (int c = 0; c < 60; ++c) header += ",x" + std::to_string(c);
  WriteText(csv(), header + "\n");
  const auto samples = ReadRunCsv(csv());
  ASSERT_FALSE(samples);
  ExpectError(samples.error(), csv(), 1, "", "65 columns in the header (at most 64)");
}

TEST_F(RunCsvBoundsTest, OverlongLineIsRefused) {
  WriteText(csv(), "t_s,y1,y2,y3,y4\n0,1,0,0,0\n0.01,1,0,0," + std::string(5000, '0') + "\n");
  const auto samples = ReadRunCsv(csv());
  ASSERT_FALSE(samples);
  ExpectError(samples.error(), csv(), 3, "", "line is 5011 bytes long (at most 4096)");
}

TEST_F(RunCsvBoundsTest, MoreThanTheMaximumSamplesIsRefusedBeforeAllocating) {
  WriteText(csv(), "t_s,y1,y2,y3,y4\n" + std::string(kMaxRunCsvSamples + 1, '\n'));
  const auto samples = ReadRunCsv(csv());
  ASSERT_FALSE(samples);
  ExpectError(samples.error(), csv(), kMaxRunCsvSamples + 2, "t_s",
              "10000001 sample lines (at most 10000000)");
}

TEST_F(RunCsvBoundsTest, ManyShortLinesFailAtTheFirstShortOne) {
  // 64 columns and a million bare line ends: 512 MB of doubles if sized by the line count.
  std::string header = "t_s,y1,y2,y3,y4";
  for (int c = 0; c < 59; ++c) header += ",x" + std::to_string(c);
  WriteText(csv(), header + "\n" + std::string(1'000'000, '\n'));
  const auto samples = ReadRunCsv(csv());
  ASSERT_FALSE(samples);
  ExpectError(samples.error(), csv(), 2, "t_s", "empty line");
}

TEST_F(RunCsvBoundsTest, RunCsvThatIsADirectoryIsNamed) {
  std::filesystem::create_directories(csv());
  const auto samples = ReadRunCsv(csv());
  ASSERT_FALSE(samples);
  ExpectError(samples.error(), csv(), 0, "", "is a directory, not a file");
}

}  // namespace
}  // namespace hrgbench::session
