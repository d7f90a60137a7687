#include "app/panel/session_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spdlog/spdlog.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <nlohmann/json.hpp>

namespace hrgbench::app {
namespace {

nlohmann::json UnitsJson(const SessionLaunch& launch) {
  nlohmann::json units = nlohmann::json::array();
  for (const auto& [position, serial] : launch.units)
    units.push_back({{"position", position}, {"serial", serial}});
  return units;
}

}  // namespace

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
  int err[2];
  if (::pipe2(err, O_CLOEXEC) != 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return std::string("cannot start: pipe: ") + std::strerror(errno);
  }
  int answers[2];
  if (::pipe2(answers, O_CLOEXEC) != 0) {
    for (const int f : {fds[0], fds[1], err[0], err[1]}) ::close(f);
    return std::string("cannot start: pipe: ") + std::strerror(errno);
  }
  std::vector<std::string> args = launch.arguments;
  args.insert(args.begin(), launch.program);
  args.emplace_back("--prompts");
  args.emplace_back("fd:4");
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    for (const int f : {fds[0], fds[1], err[0], err[1], answers[0], answers[1]}) ::close(f);
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
    ::dup2(answers[0], 4);  // the operator's answers to its prompts
    ::dup2(err[1], STDERR_FILENO);
    const int null = ::open("/dev/null", O_RDONLY);
    if (null >= 0) ::dup2(null, STDIN_FILENO);
    ::signal(SIGPIPE, SIG_DFL);
    sigset_t interrupts;
    sigemptyset(&interrupts);
    sigaddset(&interrupts, SIGINT);
    sigaddset(&interrupts, SIGTERM);
    ::sigprocmask(SIG_BLOCK, &interrupts, nullptr);
    // Nothing of the panel's (its listening socket, the browsers' connections) in the session.
    for (int f = 5; f < 1024; ++f) ::close(f);
    ::execv(argv[0], argv.data());
    std::_Exit(127);
  }
  ::close(fds[1]);
  ::close(err[1]);
  ::close(answers[0]);
  answers_fd_ = answers[1];
  open_prompt_.clear();
  prompt_answered_ = false;
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
                       {"resume", launch.resume},
                       {"operator", launch.operator_id},
                       {"units", UnitsJson(launch)}})
           .dump());
  reader_ = std::thread([this, fd = fds[0], err_fd = err[0], pid] { ReadEvents(fd, err_fd, pid); });
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

std::optional<std::string> SessionProcess::AnswerPrompt(const std::string& id, bool confirm,
                                                        const std::string& by) {
  const std::lock_guard lock(mutex_);
  if (!running_ || answers_fd_ < 0) return "no session is running";
  if (open_prompt_.empty()) return "no operator prompt is open";
  if (id != open_prompt_)
    return "prompt '" + id.substr(0, 64) + "' is not open (the open one is '" + open_prompt_ + "')";
  if (prompt_answered_) return "prompt '" + id + "' was answered already";
  const std::string line =
      nlohmann::json({{"id", id}, {"answer", confirm ? "confirm" : "abort"}, {"by", by}}).dump() +
      "\n";
  // A few hundred bytes into a pipe the child drains: never blocks (PIPE_BUF is atomic).
  const ssize_t written = ::write(answers_fd_, line.data(), line.size());
  if (written != static_cast<ssize_t>(line.size()))
    return std::string("cannot pass the answer to the session: ") + std::strerror(errno);
  prompt_answered_ = true;
  spdlog::info("panel: prompt '{}' answered {} by {}", id, confirm ? "confirm" : "abort", by);
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

std::string SessionProcess::Tail(const std::string& text) {
  std::string tail = text;
  while (!tail.empty() && (tail.back() == '\n' || tail.back() == ' ')) tail.pop_back();
  if (tail.size() <= kStderrTailBytes) return tail;
  tail.erase(0, tail.size() - kStderrTailBytes);
  const std::size_t line = tail.find('\n');
  return line == std::string::npos ? tail : tail.substr(line + 1);
}

void SessionProcess::ReadEvents(int fd, int err_fd, pid_t pid) {
  std::string pending;
  std::string stderr_tail;  // bounded: the last 2 x kStderrTailBytes
  bool saw_outcome = false;
  char buffer[65536];
  pollfd fds[2] = {{fd, POLLIN, 0}, {err_fd, POLLIN, 0}};
  const auto keep_stderr = [&](ssize_t n) {
    // The panel's stderr, as before (its log), and the tail kept for the page.
    const ssize_t written = ::write(STDERR_FILENO, buffer, static_cast<std::size_t>(n));
    (void)written;
    stderr_tail.append(buffer, static_cast<std::size_t>(n));
    if (stderr_tail.size() > 2 * kStderrTailBytes)
      stderr_tail.erase(0, stderr_tail.size() - 2 * kStderrTailBytes);
  };
  int status = 0;
  bool exited = false;
  for (;;) {
    const bool events_open = fds[0].fd >= 0;
    if (!events_open) {
      // The events are over and the child is finishing (its upload, its result): its stderr is
      // read until it has exited, never longer, since a process it started (the report's
      // Chromium) may hold the pipe open after it.
      if (::waitpid(pid, &status, WNOHANG) == pid) {
        exited = true;
        break;
      }
      if (fds[1].fd < 0) break;
    }
    if (::poll(fds, 2, events_open ? -1 : 50) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    if (fds[1].fd >= 0 && fds[1].revents != 0) {
      const ssize_t n = ::read(err_fd, buffer, sizeof buffer);
      if (n > 0) {
        keep_stderr(n);
      } else if (n == 0 || errno != EINTR) {
        ::close(err_fd);
        fds[1].fd = -1;
      }
    }
    if (fds[0].fd < 0 || fds[0].revents == 0) continue;
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      ::close(fd);
      fds[0].fd = -1;
      continue;
    }
    pending.append(buffer, static_cast<std::size_t>(n));
    std::size_t start = 0;
    for (std::size_t end; (end = pending.find('\n', start)) != std::string::npos; start = end + 1) {
      std::string line = pending.substr(start, end - start);
      // Only JSON objects go to the browsers: the child is ours, but a line is checked anyway.
      const nlohmann::json parsed = nlohmann::json::parse(line, nullptr, false);
      if (parsed.is_discarded() || !parsed.is_object()) continue;
      if (parsed.contains("type") && parsed["type"] == "outcome") saw_outcome = true;
      const std::lock_guard lock(mutex_);
      if (parsed.contains("type") && parsed["type"] == "prompt") {
        open_prompt_ = parsed.contains("id") && parsed["id"].is_string()
                           ? parsed["id"].get<std::string>()
                           : std::string();
        prompt_answered_ = false;
      } else if (parsed.contains("type") && parsed["type"] == "prompt_answered") {
        open_prompt_.clear();
      }
      Keep(std::move(line));
    }
    pending.erase(0, start);
    if (pending.size() > kMaxLineBytes) pending.clear();  // a runaway line: dropped whole
  }
  if (fds[1].fd >= 0) {
    // What the child wrote last, without waiting for whoever else holds the pipe.
    ::fcntl(err_fd, F_SETFL, ::fcntl(err_fd, F_GETFL) | O_NONBLOCK);
    for (ssize_t n; (n = ::read(err_fd, buffer, sizeof buffer)) > 0;) keep_stderr(n);
    ::close(err_fd);
  }
  if (fds[0].fd >= 0) ::close(fd);
  while (!exited && ::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  nlohmann::json exit_event = {{"type", "panel_exit"}};
  if (WIFEXITED(status)) exit_event["exit_code"] = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) exit_event["signal"] = WTERMSIG(status);
  // Ended without an outcome: what it said is the only account the page can give.
  if (!saw_outcome) {
    const std::string said = Tail(stderr_tail);
    exit_event["error"] = said.empty() ? std::string("the session process wrote nothing") : said;
  }
  const std::lock_guard lock(mutex_);
  Keep(exit_event.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  exit_event.erase("type");
  exit_event.erase("error");  // the state's "exit" says how it ended; the event says what it said
  exit_ = exit_event.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  running_ = false;
  pid_ = -1;
  if (answers_fd_ >= 0) ::close(answers_fd_);
  answers_fd_ = -1;
  open_prompt_.clear();
  spdlog::info("panel: session {} ended ({})", launch_.session_name,
               exit_.size() > 200 ? exit_.substr(0, 200) : exit_);
}

bool SessionProcess::Running() const {
  const std::lock_guard lock(mutex_);
  return running_;
}

std::string SessionProcess::StatusJson() const {
  const std::lock_guard lock(mutex_);
  if (!have_session_) return "null";
  return nlohmann::json(
             {{"running", running_},
              {"aborting", aborting_},
              {"exit", running_ ? nlohmann::json() : nlohmann::json::parse(exit_)},
              {"unit", launch_.serial},
              {"sequence", launch_.sequence},
              {"limits", launch_.limits},
              {"session", launch_.session_name},
              {"resume", launch_.resume},
              {"operator", launch_.operator_id},
              {"units", UnitsJson(launch_)},
              {"prompt", open_prompt_.empty() ? nlohmann::json() : nlohmann::json(open_prompt_)}})
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
