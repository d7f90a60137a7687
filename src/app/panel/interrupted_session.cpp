#include "app/panel/interrupted_session.hpp"

#include <signal.h>

#include "app/fixture_session.hpp"
#include "hrgbench/session/session_record.hpp"
#include "hrgbench/session/session_record_keys.hpp"

namespace hrgbench::app {
namespace {

// The signals that end a session's process in practice, by the names operators look up.
std::string SignalName(int signal) {
  switch (signal) {
    case SIGKILL:
      return "SIGKILL";
    case SIGTERM:
      return "SIGTERM";
    case SIGINT:
      return "SIGINT";
    case SIGHUP:
      return "SIGHUP";
    case SIGSEGV:
      return "SIGSEGV";
    case SIGABRT:
      return "SIGABRT";
    case SIGBUS:
      return "SIGBUS";
    case SIGFPE:
      return "SIGFPE";
    case SIGILL:
      return "SIGILL";
    case SIGPIPE:
      return "SIGPIPE";
    default:
      return "";
  }
}

}  // namespace

std::string ProcessEndReason(const nlohmann::json& exit) {
  if (exit.is_object() && exit.contains("signal") && exit["signal"].is_number_integer()) {
    const int signal = exit["signal"].get<int>();
    const std::string name = SignalName(signal);
    return "the session's process was killed by signal " + std::to_string(signal) +
           (name.empty() ? "" : " (" + name + ")");
  }
  if (exit.is_object() && exit.contains("exit_code") && exit["exit_code"].is_number_integer())
    return "the session's process exited with code " + std::to_string(exit["exit_code"].get<int>());
  return "";
}

std::optional<InterruptedSession> OpenSession(const std::filesystem::path& sessions_dir,
                                              const std::string& name, const std::string& ended) {
  const std::filesystem::path dir = sessions_dir / name;
  if (name.empty()) return std::nullopt;
  const std::string how = ended.empty() ? std::string("the session's process is gone") : ended;
  if (IsFixtureFolder(dir)) {
    const auto fixture = ReadFixtureRecord(dir);
    if (!fixture) return std::nullopt;
    InterruptedSession open;
    open.session = name;
    open.serial = "fixture";
    std::string left;
    for (const FixtureUnit& unit : fixture->units) {
      open.units.emplace_back(unit.position, unit.serial);
      const auto record = session::ReadSessionRecord(dir / unit.folder);
      // No record yet (killed before it was written) or one still "running": this unit goes on.
      if (!record || record->state == session::keys::kStateRunning)
        left += (left.empty() ? "" : ", ") + unit.position + " " + unit.serial;
    }
    if (left.empty()) return std::nullopt;
    open.reason = how + " before every unit's record was closed (" + left +
                  "); a resume continues those units, keeping the completed runs and the other "
                  "units' verdicts";
    return open;
  }
  const auto record = session::ReadSessionRecord(dir);
  if (!record || record->state != session::keys::kStateRunning) return std::nullopt;
  InterruptedSession open;
  open.session = name;
  open.serial = record->unit_serial;
  open.reason = how +
                " and left its record open (session.json says \"running\"); its completed runs "
                "are kept and a resume continues with the rest";
  return open;
}

}  // namespace hrgbench::app
