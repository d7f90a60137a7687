#include "app/panel/session_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spdlog/spdlog.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <nlohmann/json.hpp>

namespace hrgbench::app {

SessionProcess::~SessionProcess() {
  {
    const std::lock_guard lock(mutex_);
    if (running_ && pid_ > 0 && !aborting_) ::kill(pid_, SIGINT);
  }
  if (reader_.joinable()) reader_.join();
}

std::optional<std::string> SessionProcess::Start(const SessionLaunch& launch) {
  std::unique_lock lock(mutex_);
  if (running_)
    return "a session is already running on this station (unit " + launch_.serial +
           "): one session at a time; wait for it to end or abort it";
  if (reader_.joinable()) {
    lock.unlock();
    reader_.join();  // the last session's reader has seen its child end: a short wait
    lock.lock();
    if (running_) return "a session is already running on this station";
  }
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    return std::string("cannot start: pipe: ") + std::strerror(errno);
  std::vector<std::string> args = launch.arguments;
  args.insert(args.begin(), launch.program);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return std::string("cannot start: fork: ") + std::strerror(errno);
  }
  if (pid == 0) {
    // The child: the event pipe on fd 3 (dup2 clears close-on-exec), stdin from nowhere, the
    // default SIGINT disposition (hrg-bench installs its own), with SIGINT and SIGTERM blocked
    // across the exec: an Abort right after Start waits for hrg-bench's handlers (which unblock
    // them) instead of killing the session by the default action before it has a record.
    // Its own process group: a Ctrl-C at the panel's terminal reaches the panel, which aborts the
    // session once; reaching both, the session would see two interrupts (exit without a safe stop).
    ::setpgid(0, 0);
    ::dup2(fds[1], 3);
    const int null = ::open("/dev/null", O_RDONLY);
    if (null >= 0) ::dup2(null, STDIN_FILENO);
    ::signal(SIGPIPE, SIG_DFL);
    sigset_t interrupts;
    sigemptyset(&interrupts);
    sigaddset(&interrupts, SIGINT);
    sigaddset(&interrupts, SIGTERM);
    ::sigprocmask(SIG_BLOCK, &interrupts, nullptr);
    // Nothing of the panel's (its listening socket, the browsers' connections) in the session.
    for (int f = 4; f < 1024; ++f) ::close(f);
    ::execv(argv[0], argv.data());
    std::_Exit(127);
  }
  ::close(fds[1]);
  pid_ = pid;
  running_ = true;
  aborting_ = false;
  exit_ = "null";
  launch_ = launch;
  have_session_ = true;
  events_.clear();
  Keep(nlohmann::json({{"type", "panel_session"},
                       {"unit", launch.serial},
                       {"sequence", launch.sequence},
                       {"limits", launch.limits},
                       {"session", launch.session_name},
                       {"resume", launch.resume}})
           .dump());
  reader_ = std::thread([this, fd = fds[0], pid] { ReadEvents(fd, pid); });
  spdlog::info("panel: session {} {} (pid {})", launch.session_name,
               launch.resume ? "resumed" : "started", pid);
  return std::nullopt;
}

std::optional<std::string> SessionProcess::Abort() {
  const std::lock_guard lock(mutex_);
  if (!running_) return "no session is running";
  if (aborting_) return "the session is already stopping";
  aborting_ = true;
  ::kill(pid_, SIGINT);
  spdlog::info("panel: session {} aborted by the operator", launch_.session_name);
  Keep(nlohmann::json({{"type", "panel_abort"}, {"session", launch_.session_name}}).dump());
  return std::nullopt;
}

void SessionProcess::Keep(std::string line) {
  const std::uint64_t id = next_id_++;
  if (events_.size() >= kMaxKeptEvents) {
    // Past the bound keep what the page cannot rebuild (phases, results, the outcome).
    if (line.find("\"type\":\"progress\"") != std::string::npos ||
        line.find("\"type\":\"samples\"") != std::string::npos)
      return;
  }
  events_.push_back({id, std::move(line)});
  changed_.notify_all();
}

void SessionProcess::ReadEvents(int fd, pid_t pid) {
  std::string pending;
  char buffer[65536];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    pending.append(buffer, static_cast<std::size_t>(n));
    std::size_t start = 0;
    for (std::size_t end; (end = pending.find('\n', start)) != std::string::npos; start = end + 1) {
      std::string line = pending.substr(start, end - start);
      // Only JSON objects go to the browsers: the child is ours, but a line is checked anyway.
      const nlohmann::json parsed = nlohmann::json::parse(line, nullptr, false);
      if (parsed.is_discarded() || !parsed.is_object()) continue;
      const std::lock_guard lock(mutex_);
      Keep(std::move(line));
    }
    pending.erase(0, start);
    if (pending.size() > kMaxLineBytes) pending.clear();  // a runaway line: dropped whole
  }
  ::close(fd);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  nlohmann::json exit_event = {{"type", "panel_exit"}};
  if (WIFEXITED(status)) exit_event["exit_code"] = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) exit_event["signal"] = WTERMSIG(status);
  const std::lock_guard lock(mutex_);
  Keep(exit_event.dump());
  exit_event.erase("type");
  exit_ = exit_event.dump();
  running_ = false;
  pid_ = -1;
  spdlog::info("panel: session {} ended ({})", launch_.session_name, exit_event.dump());
}

bool SessionProcess::Running() const {
  const std::lock_guard lock(mutex_);
  return running_;
}

std::string SessionProcess::StatusJson() const {
  const std::lock_guard lock(mutex_);
  if (!have_session_) return "null";
  return nlohmann::json({{"running", running_},
                         {"aborting", aborting_},
                         {"exit", running_ ? nlohmann::json() : nlohmann::json::parse(exit_)},
                         {"unit", launch_.serial},
                         {"sequence", launch_.sequence},
                         {"limits", launch_.limits},
                         {"session", launch_.session_name},
                         {"resume", launch_.resume}})
      .dump();
}

std::vector<KeptEvent> SessionProcess::WaitForEvents(std::uint64_t after,
                                                     std::chrono::milliseconds wait) const {
  std::unique_lock lock(mutex_);
  const auto newer = [&] { return !events_.empty() && events_.back().id > after; };
  changed_.wait_for(lock, wait, newer);
  const auto first =
      std::upper_bound(events_.begin(), events_.end(), after,
                       [](std::uint64_t id, const KeptEvent& e) { return id < e.id; });
  return std::vector<KeptEvent>(first, events_.end());
}

std::uint64_t SessionProcess::FirstId() const {
  const std::lock_guard lock(mutex_);
  return events_.empty() ? 0 : events_.front().id;
}

}  // namespace hrgbench::app
