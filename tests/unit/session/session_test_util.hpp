#pragma once
// Helpers for the session tests: a scratch directory per test, file writing, error assertions.

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "hrgbench/session/session.hpp"

namespace hrgbench::session::testing {

// A fresh directory under the system temp dir, removed with everything in it at scope exit.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = "hrgbench_session_" + std::to_string(::getpid()) + "_" +
                       std::to_string(counter.fetch_add(1));
    if (info != nullptr) name += std::string("_") + info->name();
    for (char& c : name) {
      if (c == '/') c = '_';
    }
    path_ = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& relative) const { return path_ / relative; }

 private:
  std::filesystem::path path_;
};

inline void WriteText(const std::filesystem::path& path, std::string_view text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  ASSERT_TRUE(out.good()) << path;
}

inline std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return {};
  std::string text(static_cast<std::size_t>(in.tellg()), '\0');
  in.seekg(0);
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  return text;
}

// Checks every part of an error: file, line, field, and that the message quotes `in_message`.
inline void ExpectError(const SessionError& error, const std::filesystem::path& file,
                        std::size_t line, std::string_view field, std::string_view in_message) {
  EXPECT_EQ(error.file, file) << error.ToString();
  EXPECT_EQ(error.line, line) << error.ToString();
  EXPECT_EQ(error.field, field) << error.ToString();
  EXPECT_NE(error.message.find(in_message), std::string::npos)
      << "message lacks \"" << in_message << "\": " << error.ToString();
}

inline std::filesystem::path ReferenceDir(const std::string& name) {
  return std::filesystem::path(HRGBENCH_TEST_DATA_DIR) / "reference" / name;
}

}  // namespace hrgbench::session::testing
