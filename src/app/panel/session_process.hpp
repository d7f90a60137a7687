#pragma once
// The operator panel's one session at a time: `hrg-bench run` as a child process (the same program,
// so a panel session is exactly a command-line session), its event stream read from a pipe on the
// child's fd 3 (--events /dev/fd/3), kept for browsers that come (back) later. The child's stderr
// comes through the panel too (a pipe, copied to the panel's stderr as it comes): when the child
// ends without an outcome (a refusal, exit code 4, or a crash) its last lines go to the page in
// panel_exit's "error", so no start failure is said only in the server's log.
//
// Operator prompts: the child is started with --prompts fd:4, a pipe whose write end the panel
// keeps; its "prompt" and "prompt_answered" events say which prompt is open, and AnswerPrompt
// writes the answer a browser gave ({"id", "answer", "by"}, one line).
//
// Why a child process: Abort is then exactly what Ctrl-C does (SIGINT: table to zero, gyro safe,
// record closed ABORTED), a crash of the session cannot take the panel down, and the panel never
// touches the hardware itself. The child's stdout and stderr are the panel's stderr.
//
// Events: every line the child writes is kept (up to kMaxKeptEvents per session; beyond, progress
// and samples events are not kept, the rest still are) with an id that grows across sessions, so a
// browser that reloads gets the running session from its start and one that reconnects gets what it
// missed. The panel adds its own events: "panel_session" (a session was started or resumed from
// the panel: serial, sequence, limits, session folder name, resume, operator, units of a fixture
// [{position, serial}]) first, "panel_exit" (the child ended: exit_code, or signal; "error": the
// last lines of its stderr when it wrote no outcome) last.
//
// Threads: every method may be called from any thread (one mutex); WaitForEvents blocks the calling
// (HTTP) thread only.

#include <sys/types.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace hrgbench::app {

struct SessionLaunch {
  std::string program;                 // hrg-bench
  std::vector<std::string> arguments;  // after the program name
  std::string serial;
  std::string sequence;  // names, for the page
  std::string limits;
  std::string session_name;  // the folder's name in the sessions folder
  bool resume = false;       // `hrg-bench resume` of an interrupted session (said in panel_session)
  std::string operator_id;   // who started it (the page's operator field)
  // A fixture's units by position (position, serial); empty for a session of one unit.
  std::vector<std::pair<std::string, std::string>> units;
};

struct KeptEvent {
  std::uint64_t id;
  std::string json;  // one line, no newline
};

class SessionProcess {
 public:
  static constexpr std::size_t kMaxKeptEvents = 50000;
  static constexpr std::size_t kMaxLineBytes = 4u << 20;  // a samples event is ~40 kB
  static constexpr std::size_t kStderrTailBytes = 2048;   // what panel_exit's "error" may hold

  SessionProcess() = default;
  ~SessionProcess();  // a running child is interrupted (as Abort) and waited for
  SessionProcess(const SessionProcess&) = delete;
  SessionProcess& operator=(const SessionProcess&) = delete;

  // Starts the child. Fails, with a sentence for the operator, when one is running or the fork
  // fails.
  std::optional<std::string> Start(const SessionLaunch& launch);
  // SIGINT to the running child, once. Fails when none is running or it is already stopping.
  std::optional<std::string> Abort();
  // The answer to the operator prompt the child has open ("confirm" or "abort", by `by`), written
  // to its answer pipe (the child runs with --prompts fd:4). Fails when no session runs, no
  // prompt or another one is open, or this one was answered already.
  std::optional<std::string> AnswerPrompt(const std::string& id, bool confirm,
                                          const std::string& by);

  bool Running() const;
  // The current (or last) session: {running, aborting, exit, unit, sequence, limits, session,
  // resume, operator, units, prompt (the open prompt's id or null)} or null; `exit` is null while
  // it runs, then how the child ended:
  // {"exit_code": n} or
  // {"signal": n} (killed: its record may still say "running"; interrupted_session.hpp).
  std::string StatusJson() const;
  // Events with id > after, waiting up to `wait` for one; empty on timeout.
  std::vector<KeptEvent> WaitForEvents(std::uint64_t after, std::chrono::milliseconds wait) const;
  // The first kept id of the current session (0 when none).
  std::uint64_t FirstId() const;

 private:
  void ReadEvents(int fd, int err_fd, pid_t pid);
  // The last lines of the child's stderr, at most kStderrTailBytes (a line cut at the front).
  static std::string Tail(const std::string& text);
  void Keep(std::string line);  // mutex held

  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  pid_t pid_ = -1;
  bool running_ = false;
  bool aborting_ = false;
  SessionLaunch launch_;
  std::string exit_ = "null";  // JSON
  bool have_session_ = false;
  std::vector<KeptEvent> events_;
  std::uint64_t next_id_ = 1;
  std::thread reader_;
  int answers_fd_ = -1;      // the write end of the child's fd 4; -1 when none runs
  std::string open_prompt_;  // the child's open prompt (its "prompt" event); "" when none
  bool prompt_answered_ = false;
};

}  // namespace hrgbench::app
