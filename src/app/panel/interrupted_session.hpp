#pragma once
// A panel session whose process died with its record still open (issue 25 row 12), and so one the
// panel offers to resume (`hrg-bench resume DIR`, the same continuation as on the command line).
//
// Open: the folder's session.json reads (ReadSessionRecord) and says "state": "running". The
// session closes its record as its last step ("state": "closed" with the outcome, one atomic
// rename), so a process that ended with the record still "running" was killed (kill -9, the OOM
// killer) or exited without closing it (a full disk, a crash). A folder without a readable
// session.json (killed before the record existed) has nothing to resume and is not offered.
// A fixture's folder (fixture.json, one folder per unit) is open when the fixture's process was
// killed before every unit's record was closed: a unit whose session.json says "running", or
// which has none yet (killed before it was written); `hrg-bench resume` continues those units and
// keeps the verdicts of the others.
//
// Files only, no state: thread-safe. The folder is named by the caller (a name the panel chose,
// or one checked with IsSessionName); nothing here takes a path from a request.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hrgbench::app {

struct InterruptedSession {
  std::string session;  // the folder's name in the sessions folder
  std::string serial;   // the record's unit.serial; "fixture" for a fixture's folder
  // A fixture's units (position, serial), for the page; empty for a session of one unit.
  std::vector<std::pair<std::string, std::string>> units;
  std::string reason;  // for the operator: how the process ended, and that the record is open
};

// How a session's process ended, in words: `exit` is SessionProcess's {"exit_code": n} or
// {"signal": n}; e.g. "the session's process was killed by signal 9 (SIGKILL)".
std::string ProcessEndReason(const nlohmann::json& exit);

// The session in `sessions_dir`/`name` when its record is open; nullopt when it is closed, has no
// record or the record does not read. `ended` says how its process ended (ProcessEndReason), or
// is empty when the panel did not run it (then the reason says only that the record is open).
std::optional<InterruptedSession> OpenSession(const std::filesystem::path& sessions_dir,
                                              const std::string& name, const std::string& ended);

}  // namespace hrgbench::app
