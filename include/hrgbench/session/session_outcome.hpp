#pragma once
// How a bench session ends, and the process exit code that says so (STYLE rule 9: FAIL is the
// unit's, ERROR is the bench's). The recorder writes the outcome into session.json "outcome":
//   {"kind": "FAIL", "exit_code": 1, "reason": "...", "failed_parameters": [...], "estimate":
//   {...},
//    "verdict": {...}} (estimate: estimate_report_json.hpp; verdict: verdict_json.hpp)
//
// Exit codes: the one table of every program (exit_codes.hpp); ExitCode(kind) is the code a
// session of that kind ends with (0 PASS, 1 FAIL, 2 ERROR, 3 ABORTED), written beside the kind
// into the record. kExitBadInput (4) is never written into a record: there is no session to write
// it into. A recorder error (std::expected failure of SessionRecorder) during a session is an
// ERROR.

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hrgbench/session/exit_codes.hpp"

namespace hrgbench::bench {

enum class OutcomeKind { kPass, kFail, kError, kAborted };

constexpr int ExitCode(OutcomeKind kind) noexcept {
  switch (kind) {
    case OutcomeKind::kPass:
      return kExitOk;
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

// ToString back to the kind ("PASS" ...); none for anything else (a reader names the field then).
constexpr std::optional<OutcomeKind> ParseOutcomeKind(std::string_view text) noexcept {
  for (const OutcomeKind kind :
       {OutcomeKind::kPass, OutcomeKind::kFail, OutcomeKind::kError, OutcomeKind::kAborted}) {
    if (text == ToString(kind)) return kind;
  }
  return std::nullopt;
}

// One estimated quantity outside its limits (the verdict's finding, recorded verbatim).
struct FailedParameter {
  std::string name;  // as in the limits file, e.g. "delta_tau_s" or "residual_rms"
  double value = std::numeric_limits<double>::quiet_NaN();
  double min = -std::numeric_limits<double>::infinity();  // allowed range [min, max]
  double max = std::numeric_limits<double>::infinity();   // (non-finite: no bound; JSON null)
};

// A session that ended before its plan because its verdict could no longer change (the
// sequence's [adaptive]): after which run, of how many planned, why, and with which coverage
// factor that interim decision was taken (the closing verdict is judged with the limits' own).
struct EarlyEnd {
  int after_run = 0;     // the last run made (its id)
  int planned_runs = 0;  // the sequence's runs
  std::string why;       // "every limit decided", "delta2 proven non-conforming"
  double interim_coverage_factor = std::numeric_limits<double>::quiet_NaN();  // NaN: not recorded
  // Decided at a look this many seconds into run after_run's free run (its capture stopped then);
  // NaN: decided after the run had gone its planned length.
  double within_run_s = std::numeric_limits<double>::quiet_NaN();
};

struct SessionOutcome {
  OutcomeKind kind = OutcomeKind::kError;
  // One line a production operator can act on: "run 3: table rate not stable within 30 s",
  // "delta_tau_s outside limits". Required for every kind except PASS.
  std::string reason;
  std::vector<FailedParameter> failed_parameters;  // FAIL: at least one; other kinds: usually none
  std::optional<nlohmann::json> estimate;          // the estimate as the estimator reported it
  std::optional<nlohmann::json> verdict;           // every limit and fit check (verdict_json.hpp)
  // none: every planned run was made (or tried). Initialised, so the brace-initialised outcomes
  // written before it (five members) stay free of -Wmissing-field-initializers.
  std::optional<EarlyEnd> ended_early{};
};

}  // namespace hrgbench::bench
