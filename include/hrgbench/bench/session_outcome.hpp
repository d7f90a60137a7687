#pragma once
// How a bench session ends, and the process exit code that says so (STYLE rule 9: FAIL is the
// unit's, ERROR is the bench's). The recorder writes the outcome into session.json "outcome":
//   {"kind": "FAIL", "exit_code": 1, "reason": "...", "failed_parameters": [...], "estimate":
//   {...}}
//
// Exit codes of hrg-bench (run and resume; `check` uses 0 and kExitUsage only):
//   0  PASS     every limit met
//   1  FAIL     the unit's fault: at least one estimated parameter (or the residual RMS) is outside
//               its declared limits; `failed_parameters` names each one
//   2  ERROR    the bench's fault: timeout, bus-off, Modbus failure, too many drops, a crash of a
//               component, disk full or an unwritable session directory. Says nothing about the
//               unit.
//   3  ABORTED  the operator stopped the session (Ctrl-C, SIGTERM)
//   4  usage    bad command line, invalid or unreadable config, a session directory that cannot be
//               created or resumed (refused before any hardware moved). Never written into a
//               record: there is no session to write it into.
// A recorder error (std::expected failure of SessionRecorder) during a session is an ERROR.

#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace hrgbench::bench {

enum class OutcomeKind { kPass, kFail, kError, kAborted };

inline constexpr int kExitPass = 0;
inline constexpr int kExitFail = 1;
inline constexpr int kExitError = 2;
inline constexpr int kExitAborted = 3;
inline constexpr int kExitUsage = 4;

constexpr int ExitCode(OutcomeKind kind) noexcept {
  switch (kind) {
    case OutcomeKind::kPass:
      return kExitPass;
    case OutcomeKind::kFail:
      return kExitFail;
    case OutcomeKind::kError:
      return kExitError;
    case OutcomeKind::kAborted:
      return kExitAborted;
  }
  return kExitError;
}

// "PASS", "FAIL", "ERROR", "ABORTED": the spelling in session.json and on the terminal.
constexpr std::string_view ToString(OutcomeKind kind) noexcept {
  switch (kind) {
    case OutcomeKind::kPass:
      return "PASS";
    case OutcomeKind::kFail:
      return "FAIL";
    case OutcomeKind::kError:
      return "ERROR";
    case OutcomeKind::kAborted:
      return "ABORTED";
  }
  return "ERROR";
}

// One estimated quantity outside its limits (the verdict's finding, recorded verbatim).
struct FailedParameter {
  std::string name;  // as in the limits file, e.g. "delta_tau_s" or "residual_rms"
  double value = std::numeric_limits<double>::quiet_NaN();
  double min = -std::numeric_limits<double>::infinity();  // allowed range [min, max]
  double max = std::numeric_limits<double>::infinity();   // (non-finite: no bound; JSON null)
};

struct SessionOutcome {
  OutcomeKind kind = OutcomeKind::kError;
  // One line a production operator can act on: "run 3: table rate not stable within 30 s",
  // "delta_tau_s outside limits". Required for every kind except PASS.
  std::string reason;
  std::vector<FailedParameter> failed_parameters;  // FAIL: at least one; other kinds: usually none
  std::optional<nlohmann::json> estimate;          // the estimate as the estimator reported it
};

}  // namespace hrgbench::bench
