#include "hrgbench/session/kill_point.hpp"

#include <signal.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>

namespace hrgbench::session {
namespace {

struct Target {
  bool armed = false;
  std::string name;  // empty: any kill point
  long count = 1;    // the Nth passing
};

Target ReadTarget() {
  Target target;
  const char* text = std::getenv("HRGBENCH_TEST_KILL_AT");
  if (text == nullptr || *text == '\0') return target;
  const std::string spec = text;
  const std::size_t hash = spec.find('#');
  target.name = spec.substr(0, hash);
  if (hash != std::string::npos) target.count = std::strtol(spec.c_str() + hash + 1, nullptr, 10);
  // A malformed count arms nothing rather than killing at a point the test did not mean.
  target.armed = target.count >= 1;
  return target;
}

// HRGBENCH_TEST_KILL_LOG=FILE: every kill point passed is appended to FILE, one name a line, so
// a test can list them from one uninterrupted run and then kill at each.
void LogPassing(std::string_view name) {
  static const char* log = std::getenv("HRGBENCH_TEST_KILL_LOG");
  if (log == nullptr || *log == '\0') return;
  static std::mutex mutex;
  const std::lock_guard<std::mutex> lock(mutex);
  if (std::FILE* out = std::fopen(log, "a")) {
    std::fprintf(out, "%.*s\n", static_cast<int>(name.size()), name.data());
    std::fclose(out);
  }
}

}  // namespace

void KillPoint(std::string_view name) {
  LogPassing(name);
  static const Target target = ReadTarget();
  if (!target.armed) return;
  if (!target.name.empty() && target.name != name) return;
  static std::atomic<long> passed{0};
  if (passed.fetch_add(1) + 1 == target.count) ::raise(SIGKILL);
}

}  // namespace hrgbench::session
