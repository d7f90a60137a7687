// Every way session.json can be wrong: the error names the file, the 1-based line, the key path
// and the offending value.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "hrgbench/session/session.hpp"
#include "session_test_util.hpp"

namespace hrgbench::session {
namespace {

using testing::ExpectError;
using testing::ReadText;
using testing::ReferenceDir;
using testing::TempDir;
using testing::WriteText;

// One key per line so each case knows its line number.
constexpr const char* kValidJson = R"({
  "format": "hrgbench-session",
  "version": 1,
  "unit": {"serial": "SN-1"},
  "sample_rate_hz": 100.0,
  "runs": [
    {"id": 1, "file": "runs/run-001.csv", "omega_rad_s": -1e-4, "status": "complete"},
    {"id": 2, "file": "runs/run-002.csv", "omega_rad_s": 1e-4, "status": "complete"}
  ],
  "station": {"name": "bench-2"}
}
)";

constexpr const char* kCsv = "t_s,y1,y2,y3,y4\n0,1,0,0,0\n0.01,1,0,0,0\n";

class SessionErrorsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    WriteText(dir_ / "runs/run-001.csv", kCsv);
    WriteText(dir_ / "runs/run-002.csv", kCsv);
  }

  // Writes kValidJson with `from` replaced by `to` (which must occur) and reads the session.
  SessionError ReadWith(const std::string& from, const std::string& to,
                        const ReadOptions& options = {}) {
    std::string text = kValidJson;
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    WriteText(json_file(), text);
    const auto session = ReadSession(dir_.path(), options);
    EXPECT_FALSE(session) << "accepted:\n" << text;
    return session ? SessionError{} : session.error();
  }

  std::filesystem::path json_file() const { return dir_ / "session.json"; }

  TempDir dir_;
};

// A key twice in one object: the parser kept the last silently, so a session.json that says two
// things was read as one (issue 25 row 14). Refused, naming the field and the repeat's line.
TEST_F(SessionErrorsTest, ADuplicateKeyIsRefusedByFieldAndLine) {
  ExpectError(ReadWith("\"version\": 1,", "\"version\": 1,\n  \"version\": 2,"), json_file(), 4,
              "version", "duplicate key 'version'");
  ExpectError(ReadWith("{\"serial\": \"SN-1\"}", "{\"serial\": \"SN-1\",\n \"serial\": \"SN-2\"}"),
              json_file(), 5, "unit.serial", "duplicate key 'serial'");
  // The same key in two objects is no repeat.
  std::string text = kValidJson;
  WriteText(json_file(), text);
  EXPECT_TRUE(ReadSession(dir_.path())) << "two runs both have \"id\"";
}

TEST_F(SessionErrorsTest, TheValidSessionReads) {
  WriteText(json_file(), kValidJson);
  const auto session = ReadSession(dir_.path());
  ASSERT_TRUE(session) << session.error().ToString();
  EXPECT_EQ(session->loaded_run_ids.size(), 2u);
  EXPECT_EQ(session->document["station"]["name"], "bench-2");
}

TEST_F(SessionErrorsTest, MissingSessionJson) {
  const auto session = ReadSession(dir_.path());
  ASSERT_FALSE(session);
  ExpectError(session.error(), json_file(), 0, "", "cannot open: No such file or directory");
}

TEST_F(SessionErrorsTest, SyntaxErrorGivesTheLine) {
  // The missing comma is noticed at the next token, on line 6.
  ExpectError(ReadWith("\"sample_rate_hz\": 100.0,", "\"sample_rate_hz\": 100.0"), json_file(), 6,
              "", "parse error at line 6");
  ExpectError(ReadWith("\"version\": 1,", "\"version\": 1,,"), json_file(), 3, "", "syntax error");
  WriteText(json_file(), "");
  ExpectError(ReadSession(dir_.path()).error(), json_file(), 1, "", "unexpected end of input");
}

TEST_F(SessionErrorsTest, TopLevelNotAnObject) {
  WriteText(json_file(), "\n[1, 2]\n");
  ExpectError(ReadSession(dir_.path()).error(), json_file(), 2, "",
              "expected an object, got array [1,2]");
}

TEST_F(SessionErrorsTest, UnknownFormatOrVersion) {
  ExpectError(ReadWith("\"hrgbench-session\"", "\"hrgbench-sesion\""), json_file(), 2, "format",
              "unknown format 'hrgbench-sesion'");
  ExpectError(ReadWith("\"format\": \"hrgbench-session\",", ""), json_file(), 1, "format",
              "missing key 'format'");
  ExpectError(ReadWith("\"version\": 1", "\"version\": 2"), json_file(), 3, "version",
              "unsupported version 2");
  ExpectError(ReadWith("\"version\": 1", "\"version\": \"1\""), json_file(), 3, "version",
              "expected an integer, got string \"1\"");
  ExpectError(ReadWith("\"version\": 1", "\"version\": 1.0"), json_file(), 3, "version",
              "expected an integer, got number 1.0");
  ExpectError(ReadWith("\"version\": 1", "\"version\": 99999999999"), json_file(), 3, "version",
              "integer out of range: 99999999999");
}

TEST_F(SessionErrorsTest, UnitAndSampleRate) {
  ExpectError(ReadWith("{\"serial\": \"SN-1\"}", "{}"), json_file(), 4, "unit.serial",
              "missing key 'serial'");
  ExpectError(ReadWith("{\"serial\": \"SN-1\"}", "{\"serial\": 42}"), json_file(), 4, "unit.serial",
              "expected a string, got number 42");
  ExpectError(ReadWith("{\"serial\": \"SN-1\"}", "\"SN-1\""), json_file(), 4, "unit",
              "expected an object, got string \"SN-1\"");
  ExpectError(ReadWith("100.0", "-100.0"), json_file(), 5, "sample_rate_hz",
              "must be positive, got -100.0");
  ExpectError(ReadWith("100.0", "null"), json_file(), 5, "sample_rate_hz",
              "expected a number, got null");
  ExpectError(ReadWith("100.0", "1e999"), json_file(), 5, "sample_rate_hz",
              "number overflow parsing '1e999'");
  ExpectError(ReadWith("-1e-4", "-1e-4, \"extra\": [\"1e999\", -1e999]"), json_file(), 7,
              "runs[0].extra[1]", "number overflow parsing '-1e999'");
}

TEST_F(SessionErrorsTest, RunsArrayAndEntries) {
  ExpectError(ReadWith("\"runs\": [", "\"runz\": ["), json_file(), 1, "runs", "missing key 'runs'");
  ExpectError(ReadWith("\"runs\": [", "\"runs\": 5, \"x\": ["), json_file(), 6, "runs",
              "expected an array, got number 5");
  ExpectError(ReadWith("{\"id\": 2, \"file\": \"runs/run-002.csv\", \"omega_rad_s\": 1e-4, "
                       "\"status\": \"complete\"}",
                       "\"run 2\""),
              json_file(), 8, "runs[1]", "expected an object, got string \"run 2\"");
  ExpectError(ReadWith("\"omega_rad_s\": 1e-4", "\"omega_rad_s\": \"fast\""), json_file(), 8,
              "runs[1].omega_rad_s", "expected a number, got string \"fast\"");
  ExpectError(ReadWith("\"omega_rad_s\": -1e-4, ", ""), json_file(), 7, "runs[0].omega_rad_s",
              "missing key 'omega_rad_s'");
  ExpectError(ReadWith("\"id\": 2", "\"id\": 1"), json_file(), 8, "runs[1].id",
              "duplicate run id 1 (also runs[0].id)");
  ExpectError(ReadWith("\"id\": 2", "\"id\": 2.5"), json_file(), 8, "runs[1].id",
              "expected an integer, got number 2.5");
  ExpectError(ReadWith("\"id\": 2", "\"id\": -3"), json_file(), 8, "runs[1].id",
              "must be >= 1, got -3");
  ExpectError(ReadWith("\"status\": \"complete\"}\n  ]", "\"status\": true}\n  ]"), json_file(), 8,
              "runs[1].status", "expected a string, got boolean true");
  ExpectError(ReadWith("\"file\": \"runs/run-001.csv\"", "\"file\": [\"runs\"]"), json_file(), 7,
              "runs[0].file", "expected a string, got array [\"runs\"]");
}

TEST_F(SessionErrorsTest, RunFileEscapingTheDirectory) {
  ExpectError(ReadWith("runs/run-002.csv", "../run-002.csv"), json_file(), 8, "runs[1].file",
              "'../run-002.csv' is outside the session directory");
  ExpectError(ReadWith("runs/run-002.csv", "runs/../../x/run-002.csv"), json_file(), 8,
              "runs[1].file", "'runs/../../x/run-002.csv' is outside");
  ExpectError(ReadWith("runs/run-001.csv", "/etc/passwd"), json_file(), 7, "runs[0].file",
              "absolute path '/etc/passwd'");
  ExpectError(ReadWith("runs/run-001.csv", ""), json_file(), 7, "runs[0].file", "empty file name");
  ExpectError(ReadWith("runs/run-001.csv", "runs/"), json_file(), 7, "runs[0].file",
              "names a directory");
}

TEST_F(SessionErrorsTest, CsvErrorsNameTheRunFile) {
  WriteText(dir_ / "runs/run-002.csv", "t_s,y1,y2,y3,y4\n0,1,0,0,0\n0.01,1,zero,0,0\n");
  ExpectError(ReadWith("SN-1", "SN-1"), dir_ / "runs/run-002.csv", 3, "y2", "not a number 'zero'");
  std::filesystem::remove(dir_ / "runs/run-002.csv");
  ExpectError(ReadWith("SN-1", "SN-1"), dir_ / "runs/run-002.csv", 0, "",
              "cannot open: No such file or directory");
}

TEST_F(SessionErrorsTest, TooFewSamplesForTheOption) {
  ReadOptions options;
  options.min_samples_per_run = 3;
  ExpectError(ReadWith("SN-1", "SN-1", options), dir_ / "runs/run-001.csv", 0, "t_s",
              "2 sample(s), at least 3 required");
}

// A pretty-printed file as the prototype writes it: the line found is the value's own line.
TEST_F(SessionErrorsTest, LineOfAValueInAnIndentedReferenceFile) {
  const auto reference = ReferenceDir("paper-noisefree");
  std::string text = ReadText(reference / "session.json");
  const std::string from = "\"omega_rad_s\": 0.0,";
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, from.size(), "\"omega_rad_s\": \"zero\",");
  const std::size_t line =
      1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + at, '\n'));
  WriteText(json_file(), text);
  ExpectError(ReadSession(dir_.path()).error(), json_file(), line, "runs[2].omega_rad_s",
              "expected a number, got string \"zero\"");
}

TEST(SessionErrorTest, ToStringFormats) {
  EXPECT_EQ((SessionError{"s/session.json", 7, "runs[1].id", "duplicate"}).ToString(),
            "s/session.json:7: field 'runs[1].id': duplicate");
  EXPECT_EQ((SessionError{"s/runs/r.csv", 0, "", "cannot open"}).ToString(),
            "s/runs/r.csv: cannot open");
}

}  // namespace
}  // namespace hrgbench::session

namespace hrgbench::session {
namespace {

// runs[].end.omega_std_error_rad_s, when the bench recorded it, reaches the estimator; a value that
// is not a finite number >= 0 is refused naming it.
TEST_F(SessionErrorsTest, TheRecordedStdOfOmegaIsReadAndChecked) {
  std::string text = kValidJson;
  const std::string from = "\"omega_rad_s\": 1e-4, ";
  text.replace(text.find(from), from.size(),
               from + "\"end\": {\"omega_std_error_rad_s\": 2.5e-7}, ");
  WriteText(json_file(), text);
  const auto session = ReadSession(dir_.path());
  ASSERT_TRUE(session) << session.error().ToString();
  const std::vector<estimator::RunData> runs = ToRunData(*session);
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_TRUE(std::isnan(runs[0].omega_std_rad_s));  // not recorded
  EXPECT_EQ(runs[1].omega_std_rad_s, 2.5e-7);
  ExpectError(ReadWith(from, from + "\"end\": {\"omega_std_error_rad_s\": -1}, "), json_file(), 8,
              "runs[1].end.omega_std_error_rad_s", "expected a finite number >= 0, got -1");
  ExpectError(ReadWith(from, from + "\"end\": {\"omega_std_error_rad_s\": \"small\"}, "),
              json_file(), 8, "runs[1].end.omega_std_error_rad_s",
              "expected a number, got string \"small\"");
  // null: not measured (the record writes NaN as null).
  text = kValidJson;
  text.replace(text.find(from), from.size(), from + "\"end\": {\"omega_std_error_rad_s\": null}, ");
  WriteText(json_file(), text);
  const auto unmeasured = ReadSession(dir_.path());
  ASSERT_TRUE(unmeasured) << unmeasured.error().ToString();
  EXPECT_TRUE(std::isnan(ToRunData(*unmeasured)[1].omega_std_rad_s));
}

TEST_F(SessionErrorsTest, IqConventionMissingIsTheModelsWithANote) {
  // A session recorded before the convention was stated: the model's, said in a note.
  WriteText(json_file(), kValidJson);
  const auto session = ReadSession(dir_.path());
  ASSERT_TRUE(session) << session.error().ToString();
  EXPECT_EQ(session->iq_convention, estimator::IqConvention::kMinusSine);
  ASSERT_EQ(session->notes.size(), 1u);
  EXPECT_NE(session->notes[0].find("no electronics.iq_convention"), std::string::npos);
  EXPECT_TRUE(session->warnings.empty());
}

TEST_F(SessionErrorsTest, IqConventionPlusSineIsConjugatedForTheFit) {
  // y2 and y4 negated by ToRunData, the CSV's own samples kept as stored, and a note saying so.
  WriteText(dir_ / "runs/run-001.csv", "t_s,y1,y2,y3,y4\n0,1,0.5,0.25,-0.125\n0.01,1,2,3,4\n");
  std::string text = kValidJson;
  text.replace(text.find("\"station\""), 9,
               "\"electronics\": {\"iq_convention\": \"plus-sine\"},\n  \"station\"");
  WriteText(json_file(), text);
  const auto session = ReadSession(dir_.path());
  ASSERT_TRUE(session) << session.error().ToString();
  EXPECT_EQ(session->iq_convention, estimator::IqConvention::kPlusSine);
  ASSERT_EQ(session->notes.size(), 1u);
  EXPECT_NE(session->notes[0].find("y2 and y4 negated"), std::string::npos);
  EXPECT_EQ(session->loaded_samples[0].y(1, 0), 0.5);
  const std::vector<estimator::RunData> runs = ToRunData(*session);
  EXPECT_EQ(runs[0].y.col(0), Eigen::Vector4d(1.0, -0.5, 0.25, 0.125));
  EXPECT_EQ(runs[0].y.col(1), Eigen::Vector4d(1.0, -2.0, 3.0, -4.0));
}

TEST_F(SessionErrorsTest, IqConventionUnknownNamesFileFieldAndValue) {
  ExpectError(ReadWith("\"station\": {",
                       "\"electronics\": {\"iq_convention\": \"plus-cosine\"}, \"station\": {"),
              json_file(), 10, "electronics.iq_convention",
              "expected \"minus-sine\" or \"plus-sine\", got string \"plus-cosine\"");
  ExpectError(ReadWith("\"station\": {", "\"electronics\": {\"iq_convention\": 1}, \"station\": {"),
              json_file(), 10, "electronics.iq_convention",
              "expected \"minus-sine\" or \"plus-sine\", got number 1");
}

TEST_F(SessionErrorsTest, WriterAlwaysStatesTheIqConvention) {
  // What the writer records reads back as it was, for both conventions.
  for (const auto convention :
       {estimator::IqConvention::kMinusSine, estimator::IqConvention::kPlusSine}) {
    Session session;
    session.serial = "SN-9";
    session.sample_rate_hz = 1000.0;
    session.iq_convention = convention;
    session.runs.push_back({1, "runs/run-001.csv", 0.1, "complete"});
    ASSERT_TRUE(WriteSessionJson(dir_.path(), session));
    const auto read = ReadSession(dir_.path());
    ASSERT_TRUE(read) << read.error().ToString();
    EXPECT_EQ(read->iq_convention, convention);
    EXPECT_EQ(read->document["electronics"]["iq_convention"],
              std::string(estimator::IqConventionName(convention)));
  }
}

}  // namespace
}  // namespace hrgbench::session
