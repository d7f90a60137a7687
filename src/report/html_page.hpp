#pragma once
// The page: header, outcome, tables, per-run sections with their figures, the data block and the
// scripts (Chart.js inlined, then the code that draws every figure spec of the data block). The
// contract is in hrgbench/report/session_report.hpp. Internal to src/report.

#include <string>

#include <nlohmann/json.hpp>

#include "report_inputs.hpp"

namespace hrgbench::report::internal {

// `chart_js` is the Chart.js UMD build already made safe (ScriptSafeJavaScript).
std::string RenderHtml(const ReportInputs& inputs, const nlohmann::json& data,
                       const std::string& chart_js);

// The run a warning concerns: N for a text starting "run N" (followed by ':', ' ' or the end),
// else 0.
int WarningRun(const std::string& warning);

}  // namespace hrgbench::report::internal
