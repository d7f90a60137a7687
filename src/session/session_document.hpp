#pragma once
// Internal: the bench's additions to session.json as JSON values, and back (for resume).

#include <expected>
#include <nlohmann/json.hpp>
#include <string>

#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_outcome.hpp"
#include "hrgbench/session/session_record_types.hpp"

namespace hrgbench::bench::internal {

// "runs/run-007.csv" (at least three digits).
std::string RunFileName(int run_id);

// {"utc": "2024-05-01T12:00:00.123456Z", "monotonic_ns": N}, both taken now.
nlohmann::json TimeStampNow();

// A double as JSON: null when not finite (JSON has no NaN; nlohmann would write null anyway, this
// makes the intent visible).
nlohmann::json Number(double value);

nlohmann::json ToJson(const PlannedRun& plan);
nlohmann::json ToJson(const RunStart& start);
nlohmann::json ToJson(const RunEnd& end, std::uint64_t samples);
nlohmann::json ToJson(const SessionOutcome& outcome);

// Reads a "plan" object written by ToJson(PlannedRun); the message names the bad key.
std::expected<PlannedRun, std::string> PlanFromJson(const nlohmann::json& plan, int run_id);

// Problems a header has (empty when none): the first one, naming the field.
std::string HeaderProblem(const SessionHeader& header);

RecordError FromSessionError(const session::SessionError& error);

}  // namespace hrgbench::bench::internal
