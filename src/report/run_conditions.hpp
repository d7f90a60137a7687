#pragma once
// The conditions over a run (issue 26 §4: not only at its start and end): the unit's temperature
// from the run CSV's temp_c column when the electronics recorded one per sample, else the
// recorded start and end only, said so; the resonant frequency as the record holds it (at the
// release, at the run's start and end: session.json keeps no series of it, and the report does not
// decode the electronics' status frames of the raw CAN log), said so. Internal to src/report.

#include <nlohmann/json.hpp>

#include "hrgbench/report/decimate.hpp"
#include "hrgbench/session/session_record.hpp"
#include "report_inputs.hpp"

namespace hrgbench::report::internal {

// The numbers of the run's capture-quality block (derived.runs["<id>"]): temperature_over_run
// ("temp_c" or null), temperature_min_c / _max_c / _samples (when temp_c), frequency_over_run
// (null: not recorded over the run).
void AddRunConditions(const RunView& run, nlohmann::json* quality);

// conditions-run-N: temperature (left axis; temp_c decimated onto the run's time axis as every
// series, or the recorded start and end joined by a dashed line) and the resonant frequency
// (right axis; the recorded start and end, dashed), against t. Nothing when the record has
// neither (no temp_c, no start or end value).
void AddConditionsFigure(const RunView& run, const session::RunRecord& recorded,
                         const MinMaxDecimator& decimator, nlohmann::json* figures);

}  // namespace hrgbench::report::internal
