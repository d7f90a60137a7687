#pragma once
// The judge of a recorded session: the one home of the PASS/FAIL/ERROR policy (STYLE rule 9: FAIL
// is the unit's, ERROR is the bench's). The sequencer calls it at the end of every session with
// the estimate it made from the record; a fixture's aggregate and what a resume keeps of a closed
// session are decided here too. Everything here is a pure function of its inputs: no I/O, no
// hardware, no clock; thread-safe; allocates (not for real-time code).
//
// The policy, in the order it is applied (the first that holds decides):
//   1. the estimate is not usable (EstimateSummary::IsUsable false)     ERROR "estimate not usable:
//                                                                         <the estimator's
//                                                                         message>"
//   2. the record's electronics cannot be read (engineering of record)   ERROR "the record's
//                                                                         electronics: <why>"
//   3. the verdict (EvaluateLimits with the engineering of record):
//      a limit failed (proven outside, or undecided in its guard band)   FAIL "out of limits: a, b"
//                                                                         [+ "; not accepted within
//                                                                         the guard band (k = 2):
//                                                                         c, retest the unit"]
//                                                                         [+ "; not judged: ..."]
//      the fit is outside its model (no limit judged)                    ERROR "the fit is outside
//                                                                         its model, no limit
//                                                                         judged: <fit problems>"
//      a limit could not be judged (held parameter, too uncertain)       ERROR "limits not judged:
//                                                                         <each limit's message>"
//      every declared limit judged and met (or none declared)            PASS
// PASS means every declared limit was judged and met: a limit the bench could not judge is the
// bench's failure (ERROR), and a limit that failed is the unit's whatever else could not be judged.

#include <expected>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hrgbench/analysis/engineering_of_record.hpp"
#include "hrgbench/analysis/verdict.hpp"
#include "hrgbench/config/limits_config.hpp"
#include "hrgbench/estimator/engineering_quantities.hpp"
#include "hrgbench/estimator/summary.hpp"
#include "hrgbench/session/session_outcome.hpp"
#include "hrgbench/session/session_record.hpp"

namespace hrgbench::bench {

// What the judge decided about one session (the outcome the record closes with, less the estimate
// JSON, which is the caller's: it made the estimate).
struct SessionJudgement {
  OutcomeKind kind = OutcomeKind::kError;
  std::string reason;                              // one line; never empty
  std::vector<FailedParameter> failed_parameters;  // FAIL: each limit that failed, in file order
  std::optional<Verdict> verdict;                  // when the limits were applied (policy step 3)
  // The estimate in the field's units with the record's f0 and pick-off declaration; when the
  // limits were applied.
  std::optional<estimator::EngineeringQuantities> engineering;

  // The record's outcome: kind, reason, failed parameters, the verdict as JSON (verdict_json.hpp)
  // and `estimate` (the estimate report the caller recorded, or none).
  SessionOutcome ToOutcome(std::optional<nlohmann::json> estimate) const;
};

// The policy above on typed inputs. `engineering`: the engineering of record of `estimate`
// (ComputeEngineeringOfRecord), or why it could not be computed; read only when the estimate is
// usable.
SessionJudgement JudgeSession(const estimator::EstimateSummary& estimate,
                              const std::expected<EngineeringOfRecord, std::string>& engineering,
                              const LimitsConfig& limits);

// The same on a record: the engineering of record computed from `record` (session.json as read
// back by session::ReadSessionRecord, which named a malformed declaration already) only when the
// estimate is usable.
SessionJudgement JudgeRecordedSession(const estimator::EstimateSummary& estimate,
                                      const session::SessionRecord& record,
                                      const LimitsConfig& limits);

// How bad an outcome is, for an aggregate: PASS < FAIL < ERROR < ABORTED (an operator's stop
// outranks a fault, which says nothing about the unit; a unit's FAIL outranks a PASS).
int Severity(OutcomeKind kind) noexcept;

// A fixture's outcome: its worst unit's (Severity); PASS for no units (nothing was required).
OutcomeKind FixtureOutcome(std::span<const OutcomeKind> units) noexcept;
// The fixture's exit code (exit_codes.hpp): ExitCode(FixtureOutcome(units)).
int FixtureExitCode(std::span<const OutcomeKind> units) noexcept;

// What a resume of a fixture keeps of a unit's session that already closed: its verdict when it
// closed with one (PASS or FAIL: the unit was judged); nothing when it closed as ERROR or ABORTED
// (the bench owes it a verdict: it runs again), or is not closed (interrupted: it continues).
bool KeepsVerdict(bool closed, OutcomeKind kind) noexcept;
// The reason a kept verdict is reported with: "kept from before: <the recorded reason>".
std::string KeptReason(std::string_view recorded_reason);

}  // namespace hrgbench::bench
