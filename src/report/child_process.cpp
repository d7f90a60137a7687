#include "child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <thread>

namespace hrgbench::report::internal {

std::string ChildResult::Describe(const std::string& program) const {
  std::string text;
  if (!started)
    text = program + " could not be started (not installed?)";
  else if (timed_out)
    text = program + " was killed after its time limit";
  else if (exit_code < 0)
    text = program + " ended by a signal";
  else
    text = program + " exited with " + std::to_string(exit_code);
  std::string tail = output.substr(0, 400);
  while (!tail.empty() && (tail.back() == '\n' || tail.back() == ' ')) tail.pop_back();
  if (!tail.empty()) text += ": " + tail;
  return text;
}

namespace {

// "<prefix><pid>-XXXXXX": the owner's pid in the name, so a folder whose owner died (kill -9 while
// Chromium or gnuplot ran) is found and removed by the next report on this machine.
bool OwnerIsGone(const std::string& name, const std::string& prefix) {
  if (name.rfind(prefix, 0) != 0) return false;
  const std::string rest = name.substr(prefix.size());
  const std::size_t dash = rest.find('-');
  if (dash == std::string::npos || dash == 0) return false;
  char* end = nullptr;
  const long pid = std::strtol(rest.c_str(), &end, 10);
  if (end != rest.c_str() + dash || pid <= 0 || pid == ::getpid()) return false;
  return ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
}

void RemoveStaleTemporaryDirectories(const std::filesystem::path& base) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(base, ec)) {
    const std::string name = entry.path().filename().string();
    for (const char* prefix :
         {"hrg-report-child-", "hrg-report-figures-", "hrg-report-chromium-"}) {
      std::error_code removed;
      if (OwnerIsGone(name, prefix)) std::filesystem::remove_all(entry.path(), removed);
    }
  }
}

}  // namespace

std::string MakeTemporaryDirectory(const std::string& prefix) {
  std::error_code ec;
  const std::filesystem::path base = std::filesystem::temp_directory_path(ec);
  if (ec) return {};
  RemoveStaleTemporaryDirectories(base);
  std::string pattern = (base / (prefix + std::to_string(::getpid()) + "-XXXXXX")).string();
  if (::mkdtemp(pattern.data()) == nullptr) return {};
  return pattern;
}

ChildResult RunChild(const std::vector<std::string>& argv, double timeout_s) {
  ChildResult result;
  if (argv.empty()) return result;
  const std::string dir = MakeTemporaryDirectory("hrg-report-child-");
  if (dir.empty()) return result;
  const std::string log = dir + "/output.txt";
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  // fork, not posix_spawn: the child must die with this process (PR_SET_PDEATHSIG) and lead its
  // own process group (a timeout kills the group). Only async-signal-safe calls before exec.
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(126);  // the parent died before the line above
    const int in = ::open("/dev/null", O_RDONLY);
    const int out = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (in < 0 || out < 0) ::_exit(127);
    ::dup2(in, 0);
    ::dup2(out, 1);
    ::dup2(out, 2);
    ::execvp(args[0], args.data());
    ::_exit(127);
  }
  const int spawned = pid > 0 ? 0 : errno;
  if (spawned == 0) {
    result.started = true;
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::milliseconds(static_cast<long long>(timeout_s * 1000.0));
    int status = 0;
    for (;;) {
      const pid_t done = ::waitpid(pid, &status, WNOHANG);
      if (done == pid) break;
      if (done < 0 && errno != EINTR) break;
      if (std::chrono::steady_clock::now() > deadline) {
        ::kill(-pid, SIGKILL);  // its group: what it started too
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &status, 0);
        result.timed_out = true;
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (!result.timed_out && WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
    // The child exits 127 when the program cannot be executed (not installed).
    if (result.exit_code == 127) result.started = false;
    const int fd = ::open(log.c_str(), O_RDONLY);
    if (fd >= 0) {
      char buffer[4096];
      const ssize_t n = ::read(fd, buffer, sizeof buffer);
      if (n > 0) result.output.assign(buffer, static_cast<std::size_t>(n));
      ::close(fd);
    }
  }
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  return result;
}

}  // namespace hrgbench::report::internal
