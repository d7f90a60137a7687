// The default session folder (session_folder.hpp): the name from the serial and the UTC time, a
// suffix when the name is taken, and a serial that could escape the folder refused.

#include "app/session_folder.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>

namespace hrgbench::app {
namespace {

namespace fs = std::filesystem;

class SessionFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device rd;
    dir_ = fs::temp_directory_path() / ("hrgbench-folder-" + std::to_string(rd()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path dir_;
};

// 1764000000 s after the epoch is 2025-11-24 16:00:00 UTC (Python's datetime.fromtimestamp).
constexpr std::time_t kNow = 1764000000;

TEST_F(SessionFolderTest, SerialAndUtcTimeInTheSessionsFolder) {
  const auto folder = NewSessionFolder(dir_, "SN-0001", kNow);
  ASSERT_TRUE(folder.has_value()) << folder.error();
  EXPECT_EQ(*folder, dir_ / "SN-0001-20251124T160000Z");
  EXPECT_FALSE(fs::exists(*folder));  // creates nothing
}

TEST_F(SessionFolderTest, ATakenNameGetsTheNextSuffix) {
  fs::create_directories(dir_ / "SN-0001-20251124T160000Z");
  fs::create_directories(dir_ / "SN-0001-20251124T160000Z-2");
  const auto folder = NewSessionFolder(dir_, "SN-0001", kNow);
  ASSERT_TRUE(folder.has_value()) << folder.error();
  EXPECT_EQ(*folder, dir_ / "SN-0001-20251124T160000Z-3");
}

TEST_F(SessionFolderTest, ASerialThatWouldLeaveTheFolderIsRefused) {
  for (const std::string serial : {"../etc", "a/b", ".hidden", "", "-rf"}) {
    const auto folder = NewSessionFolder(dir_, serial, kNow);
    ASSERT_FALSE(folder.has_value()) << serial;
    EXPECT_EQ(folder.error().rfind("serial: ", 0), 0u) << folder.error();
  }
}

}  // namespace
}  // namespace hrgbench::app
