#pragma once
// The conditions over a run (issue 26 §4: not only at its start and end): the unit's temperature
// and resonant frequency from the run CSV's temp_c and freq_hz columns (the electronics' last
// status report at each sample, as the bench records them) when the run has them, else the
// recorded start and end only, said so. Internal to src/report.

#include <nlohmann/json.hpp>

#include "hrgbench/report/decimate.hpp"
#include "hrgbench/session/session_record.hpp"
#include "report_inputs.hpp"

namespace hrgbench::report::internal {

// The numbers of the run's capture-quality block (derived.runs["<id>"]), per condition:
// temperature_over_run ("temp_c" or null) with temperature_min_c / _max_c / _samples when
// recorded; frequency_over_run ("freq_hz" or null) with frequency_min_hz / _max_hz / _samples.
void AddRunConditions(const RunView& run, nlohmann::json* quality);

// conditions-run-N: temperature (left axis) and resonant frequency (right axis) against t, each
// from its column decimated onto the run's time axis as every series, or the recorded start and
// end joined by a dashed line. Nothing when the record has neither.
void AddConditionsFigure(const RunView& run, const session::RunRecord& recorded,
                         const MinMaxDecimator& decimator, nlohmann::json* figures);

}  // namespace hrgbench::report::internal
