#pragma once
// A folder a test made, removed when the test is done with it: also when an ASSERT returned early.
// A failed test keeps it and says where, for a look (a flaky failure's record is the evidence).

#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <system_error>
#include <utility>

namespace hrgbench::testing {

// A bench session's folder is ~120 MB: a suite that leaves them behind fills a CI machine's disk.
class RemovedAtEnd {
 public:
  RemovedAtEnd() = default;
  explicit RemovedAtEnd(std::filesystem::path path) : path_(std::move(path)) {}
  RemovedAtEnd(RemovedAtEnd&& other) noexcept : path_(std::exchange(other.path_, {})) {}
  RemovedAtEnd& operator=(RemovedAtEnd&& other) noexcept {
    if (this != &other) {
      Remove();
      path_ = std::exchange(other.path_, {});
    }
    return *this;
  }
  RemovedAtEnd(const RemovedAtEnd&) = delete;
  RemovedAtEnd& operator=(const RemovedAtEnd&) = delete;
  ~RemovedAtEnd() { Remove(); }

 private:
  void Remove() {
    if (path_.empty()) return;
    if (::testing::Test::HasFailure()) {
      std::cerr << "kept for a look (the test failed): " << path_.string() << "\n";
      return;
    }
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  std::filesystem::path path_;
};

}  // namespace hrgbench::testing
