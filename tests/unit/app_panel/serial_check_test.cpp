// A serial from the page becomes part of a folder name only if SerialProblem accepts it: every way
// out of the sessions folder, and every character a file system or a shell treats specially, is
// refused with a sentence that says why.
#include "app/serial_check.hpp"

#include <gtest/gtest.h>

#include <string>

namespace hrgbench::app {
namespace {

TEST(SerialCheck, AcceptsWhatSerialsLookLike) {
  for (const char* serial : {"SN1", "HRG-2026-0042", "a.b_c-d", "0", "X9.rev2"})
    EXPECT_EQ(SerialProblem(serial), std::nullopt) << serial;
  EXPECT_EQ(SerialProblem(std::string(kMaxSerialLength, 'A')), std::nullopt);
}

TEST(SerialCheck, RefusesEveryWayOutOfTheFolder) {
  const auto problem = [](std::string_view s) { return SerialProblem(s).value_or("accepted"); };
  EXPECT_EQ(problem(""), "the serial is empty");
  EXPECT_NE(problem("../x").find("'/'"), std::string::npos);
  EXPECT_NE(problem("..").find("start with a letter or a digit"), std::string::npos);
  EXPECT_NE(problem("a..b").find("\"..\""), std::string::npos);
  EXPECT_NE(problem(".hidden").find("start with a letter or a digit"), std::string::npos);
  EXPECT_NE(problem("-rf").find("start with a letter or a digit"), std::string::npos);
  EXPECT_NE(problem("a\\b").find("'\\'"), std::string::npos);
  EXPECT_NE(problem("a b").find("' '"), std::string::npos);
  EXPECT_NE(problem("SN\x01").find("control character (code 1) at position 3"), std::string::npos);
  EXPECT_NE(problem("SN\x7f").find("control character"), std::string::npos);
  EXPECT_NE(problem("SN\n1").find("control character"), std::string::npos);
  EXPECT_NE(problem("S\xc3\xa9").find("'?' at position 2"), std::string::npos);  // é, never echoed
  EXPECT_EQ(problem(std::string(10240, 'A')),
            "the serial is too long: 10240 characters, at most 64");
  EXPECT_EQ(problem(std::string(kMaxSerialLength + 1, 'A')),
            "the serial is too long: 65 characters, at most 64");
}

}  // namespace
}  // namespace hrgbench::app
