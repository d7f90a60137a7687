#pragma once
// The page's data block (<script type="application/json" id="report-data">): every figure as a
// generic spec that both the page's Chart.js code and the gnuplot figures draw, and every number
// the report derives itself. Internal to src/report.
//
//   figures  [{name, caption, type: "line" | "bar", x_label, y_label, y_log, x_log (optional),
//              equal_aspect, x [number] (line) | labels [string] (bar),
//              series [{label, y [number|null], x [number] (optional, own abscissa), model,
//                       points (optional: markers at the values)}]}]
//   derived  {estimate (the re-run's EstimateReportJson), crlb {delta_std[6], xi_std[4], valid,
//             message}, anisotropy {...}, runs {"<id>": {...capture quality...}},
//             tune (tune_data.hpp; null when the unit was not tuned),
//             unit_history {store, unavailable, count, sessions [...]} (null without a store)}
//
// Long runs are decimated min/max per bucket (decimate.hpp), values rounded to 6 digits; only the
// runs whose RunView::figures is set have figures (ReportOptions::max_runs_with_figures).
//
// The runs' parts are made one run at a time (BuildRunPart), while that run's samples are in
// memory, and the samples are dropped before the next run is read: the page's data block, not the
// session's samples, is what the report keeps.

#include <cstddef>
#include <nlohmann/json.hpp>
#include <vector>

#include "report_inputs.hpp"

namespace hrgbench::report::internal {

// One run's part of the data block: derived.runs["<id>"] (capture quality) and, when run.figures,
// its seven figures. Needs run.data (and run.fitted_* to draw the model and what it left);
// `noise_sigma` the estimate's σ̂ (a run's own recorded σ̂ takes precedence).
struct RunPart {
  nlohmann::json quality;
  nlohmann::json figures = nlohmann::json::array();
};
RunPart BuildRunPart(const RunView& run, const session::SessionRecord& record,
                     const estimator::Xi& xi, double noise_sigma,
                     std::size_t max_points_per_series);

// The whole block from the inputs and each loaded run's part (`run_parts` parallel to
// inputs.runs; a run not loaded has an empty part).
nlohmann::json BuildReportData(const ReportInputs& inputs, std::vector<RunPart> run_parts);

// A number at a JSON pointer of `doc`, NaN when absent, null or not a number.
double NumberAt(const nlohmann::json& doc, const std::string& pointer);
// The value at a pointer, or nullptr when the pointer does not resolve.
const nlohmann::json* At(const nlohmann::json& doc, const std::string& pointer);

}  // namespace hrgbench::report::internal
