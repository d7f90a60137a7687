#pragma once
// Tests that need something from outside the project (a tool such as can-utils' log2asc or socat, a
// tmpfs mount) skip on a developer's machine that lacks it, and FAIL in a strict run: under CI=true
// or HRGBENCH_STRICT=1 (which scripts/run-tests.sh, the README's test command, sets), because there
// scripts/setup-debian.sh has installed everything and a skip would report an untested part green.

#include <gtest/gtest.h>

#include <cstdlib>
#include <string_view>

namespace hrgbench::testing {

inline bool StrictRun() {
  const char* ci = std::getenv("CI");
  const char* strict = std::getenv("HRGBENCH_STRICT");
  return (ci != nullptr && std::string_view(ci) == "true") ||
         (strict != nullptr && std::string_view(strict) == "1");
}

}  // namespace hrgbench::testing

// Use at the top of a TEST body (or SetUp): skips, or fails in a strict run, when `available` is
// false. `what` says what is missing and how to get it.
#define HRGBENCH_REQUIRE(available, what)                                    \
  do {                                                                       \
    if (!(available)) {                                                      \
      if (::hrgbench::testing::StrictRun()) {                                \
        GTEST_FAIL() << what << " (required: CI=true or HRGBENCH_STRICT=1; " \
                     << "scripts/setup-debian.sh installs it)";              \
      }                                                                      \
      GTEST_SKIP() << what;                                                  \
    }                                                                        \
  } while (false)
