// Every way a run CSV can be wrong: the error names the file, the 1-based line, the column and
// the offending text.

#include <gtest/gtest.h>

#include <string>

#include "hrgbench/session/session.hpp"
#include "session_test_util.hpp"

namespace hrgbench::session {
namespace {

using testing::ExpectError;
using testing::TempDir;
using testing::WriteText;

constexpr const char* kHeader = "t_s,y1,y2,y3,y4\n";

class CsvErrorsTest : public ::testing::Test {
 protected:
  // Writes `text` and reads it, expecting an error.
  SessionError Read(const std::string& text, std::size_t min_samples = 2) {
    WriteText(file_, text);
    const auto samples = ReadRunCsv(file_, min_samples);
    EXPECT_FALSE(samples) << "accepted:\n" << text;
    return samples ? SessionError{} : samples.error();
  }

  TempDir dir_;
  std::filesystem::path file_ = dir_ / "runs/run-007.csv";
};

TEST_F(CsvErrorsTest, MissingFile) {
  const auto samples = ReadRunCsv(file_);
  ASSERT_FALSE(samples);
  ExpectError(samples.error(), file_, 0, "", "cannot open: No such file or directory");
}

TEST_F(CsvErrorsTest, EmptyFile) { ExpectError(Read(""), file_, 1, "", "empty file"); }

TEST_F(CsvErrorsTest, BadHeader) {
  ExpectError(Read("t_s,y1,y2,y4\n0,1,2,3\n1,1,2,3\n"), file_, 1, "y3",
              "header lacks required column 'y3': 't_s,y1,y2,y4'");
  ExpectError(Read("time,y1,y2,y3,y4\n"), file_, 1, "t_s", "lacks required column 't_s'");
  ExpectError(Read("t_s,y1,y2,y3,y4,y2\n0,1,2,3,4,5\n"), file_, 1, "y2",
              "duplicate column 'y2' (columns 3 and 6)");
  ExpectError(Read("t_s,y1,,y2,y3,y4\n"), file_, 1, "column 3", "empty column name");
  ExpectError(Read("t_s,y1,y2,y3,y4,\n"), file_, 1, "column 6", "empty column name");
  ExpectError(Read("t_s, y1,y2,y3,y4\n"), file_, 1, "y1", "lacks required column 'y1'");
}

TEST_F(CsvErrorsTest, NonFiniteValues) {
  ExpectError(Read(std::string(kHeader) + "0,1,2,3,4\n0.01,1,nan,3,4\n"), file_, 3, "y2",
              "non-finite value 'nan'");
  ExpectError(Read(std::string(kHeader) + "0,1,2,3,4\n0.01,1,2,3,-inf\n"), file_, 3, "y4",
              "non-finite value '-inf'");
  ExpectError(Read(std::string(kHeader) + "inf,1,2,3,4\n0.01,1,2,3,4\n"), file_, 2, "t_s",
              "non-finite value 'inf'");
  ExpectError(Read(std::string(kHeader) + "0,1e999,2,3,4\n0.01,1,2,3,4\n"), file_, 2, "y1",
              "number out of the range of double '1e999'");
}

TEST_F(CsvErrorsTest, UnparsableNumbers) {
  ExpectError(Read(std::string(kHeader) + "0,1,2,3,4\n0.01,1.0abc,2,3,4\n"), file_, 3, "y1",
              "not a number '1.0abc'");
  ExpectError(Read(std::string(kHeader) + "0,1,,3,4\n"), file_, 2, "y2", "not a number ''");
  ExpectError(Read(std::string(kHeader) + "0,1,2,3,0x10\n"), file_, 2, "y4", "not a number '0x10'");
  ExpectError(Read(std::string(kHeader) + "0,1, 2,3,4\n"), file_, 2, "y2", "not a number ' 2'");
  ExpectError(Read(std::string(kHeader) + "0,+1,2,3,4\n"), file_, 2, "y1", "not a number '+1'");
  ExpectError(Read(std::string(kHeader) + "0,1,2,3,\"4\"\n"), file_, 2, "y4",
              "not a number '\"4\"'");
  ExpectError(Read(std::string(kHeader) + "0,1,2,3,4 \n"), file_, 2, "y4", "not a number '4 '");
}

TEST_F(CsvErrorsTest, WrongColumnCount) {
  ExpectError(Read(std::string(kHeader) + "0,1,2,3,4\n0.01,1,2,3\n"), file_, 3, "y4",
              "line has 4 fields, header has 5: '0.01,1,2,3'");
  ExpectError(Read(std::string(kHeader) + "0,1,2,3,4,5\n"), file_, 2, "column 6",
              "line has 6 fields, header has 5");
  ExpectError(Read(std::string(kHeader) + "0,1,2,3,4\n\n0.02,1,2,3,4\n"), file_, 3, "t_s",
              "empty line");
  ExpectError(Read(std::string(kHeader) + "0,1,2,3,4\n0.01,1,2,3,4\n\n"), file_, 4, "t_s",
              "empty line");
}

TEST_F(CsvErrorsTest, NonIncreasingTime) {
  ExpectError(Read(std::string(kHeader) + "0,1,2,3,4\n0.01,1,2,3,4\n0.01,1,2,3,4\n"), file_, 4,
              "t_s", "time not strictly increasing: 0.01 after 0.01 on line 3");
  ExpectError(Read("y1,y2,t_s,y3,y4\n1,2,0.5,3,4\n1,2,0.25,3,4\n"), file_, 3, "t_s",
              "0.25 after 0.5");
}

TEST_F(CsvErrorsTest, TooFewSamples) {
  ExpectError(Read(kHeader), file_, 0, "t_s", "0 sample(s), at least 2 required");
  ExpectError(Read(std::string(kHeader) + "0,1,2,3,4\n"), file_, 0, "t_s",
              "1 sample(s), at least 2 required");
  ExpectError(Read(std::string(kHeader) + "0,1,2,3,4\n1,1,2,3,4\n", 100), file_, 0, "t_s",
              "2 sample(s), at least 100 required");
}

}  // namespace
}  // namespace hrgbench::session
