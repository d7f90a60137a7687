#include "child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <thread>

extern char** environ;

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

std::string MakeTemporaryDirectory(const std::string& prefix) {
  std::error_code ec;
  const std::filesystem::path base = std::filesystem::temp_directory_path(ec);
  if (ec) return {};
  std::string pattern = (base / (prefix + "XXXXXX")).string();
  if (::mkdtemp(pattern.data()) == nullptr) return {};
  return pattern;
}

ChildResult RunChild(const std::vector<std::string>& argv, double timeout_s) {
  ChildResult result;
  if (argv.empty()) return result;
  const std::string dir = MakeTemporaryDirectory("hrg-report-child-");
  if (dir.empty()) return result;
  const std::string log = dir + "/output.txt";
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = -1;
  const int spawned = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
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
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &status, 0);
        result.timed_out = true;
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (!result.timed_out && WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
    // posix_spawnp reports a missing program as exit 127 of the child on glibc.
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
