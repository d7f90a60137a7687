#pragma once
// Runs an external program (gnuplot, chromium) and waits for it, with a time limit. Internal to
// src/report. POSIX and Linux (fork, PR_SET_PDEATHSIG); the estimator never sees this.

#include <string>
#include <vector>

namespace hrgbench::report::internal {

struct ChildResult {
  bool started = false;  // false: the program was not found or could not be started
  bool timed_out = false;
  int exit_code = -1;  // when it exited normally; -1 otherwise (signal, timeout, not started)
  std::string output;  // its stdout and stderr, the first 4 KiB
  std::string Describe(const std::string& program) const;  // "gnuplot exited with 1: <output>"
};

// argv[0] is looked up on PATH. stdin is /dev/null. Kills the child and its process group
// (SIGKILL) after timeout_s. The child gets SIGKILL when this process dies (kill -9 included), so
// no Chromium or gnuplot outlives a killed report.
ChildResult RunChild(const std::vector<std::string>& argv, double timeout_s);

// A fresh private directory under the system's temporary directory, "<prefix><pid>-XXXXXX";
// empty on failure. Removes first the ones of this naming whose process is gone (a killed report).
std::string MakeTemporaryDirectory(const std::string& prefix);

}  // namespace hrgbench::report::internal
