#pragma once
// The page's data block (<script type="application/json" id="report-data">): every figure as a
// generic spec that both the page's Chart.js code and the gnuplot figures draw, and every number
// the report derives itself. Internal to src/report.
//
//   figures  [{name, caption, type: "line" | "bar", x_label, y_label, y_log, equal_aspect,
//              x [number] (line) | labels [string] (bar),
//              series [{label, y [number|null], x [number] (optional, own abscissa), model}]}]
//   derived  {estimate (the re-run's EstimateReportJson), crlb {delta_std[6], xi_std[4], valid,
//             message}, anisotropy {...}, runs {"<id>": {...capture quality...}},
//             unit_history {store, unavailable, count, sessions [...]} (null without a store)}
//
// Long runs are decimated min/max per bucket (decimate.hpp), values rounded to 6 digits.

#include <cstddef>
#include <nlohmann/json.hpp>

#include "report_inputs.hpp"

namespace hrgbench::report::internal {

nlohmann::json BuildReportData(const ReportInputs& inputs, std::size_t max_points_per_series);

// A number at a JSON pointer of `doc`, NaN when absent, null or not a number.
double NumberAt(const nlohmann::json& doc, const std::string& pointer);
// The value at a pointer, or nullptr when the pointer does not resolve.
const nlohmann::json* At(const nlohmann::json& doc, const std::string& pointer);

}  // namespace hrgbench::report::internal
