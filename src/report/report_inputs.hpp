#pragma once
// What the page, the figures and the data block are made from: the session as read, the runs that
// could be loaded, the re-run estimate and each run's fitted model. Internal to src/report.

#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "hrgbench/estimator/fitted_output.hpp"
#include "hrgbench/estimator/run_data.hpp"
#include "hrgbench/estimator/summary.hpp"
#include "hrgbench/report/session_report.hpp"

namespace hrgbench::report::internal {

// One entry of session.json "runs", and what became of it.
struct RunView {
  int id = 0;
  std::size_t index = 0;          // position in session.json "runs" (for JSON pointers)
  std::string status;             // runs[].status as recorded
  std::string file;               // runs[].file
  bool loaded = false;            // its samples are in `data`
  std::string not_loaded_reason;  // why not (status, missing file, empty, unreadable)
  estimator::RunData data;        // id, Ω, t_s, y (when loaded)
  // The fitted model at data.t_s (empty when the estimate has no entry for this run).
  estimator::RunChannels fitted_y;
  estimator::RunChannels fitted_x;
};

struct ReportInputs {
  std::filesystem::path session_dir;
  nlohmann::json document;  // session.json as recorded
  double sample_rate_hz = 0.0;  // the session's (session::Session::sample_rate_hz)
  std::vector<RunView> runs;
  // The re-run estimate (method ml), when at least one run could be loaded.
  std::optional<estimator::EstimateSummary> summary;
  nlohmann::json estimate_json;  // EstimateReportJson of `summary` (null when none)
  // Warnings, each once, in the order found: the session reader's, the recorded estimate's, the
  // re-run's, the report's own.
  std::vector<std::string> warnings;
  std::optional<UnitHistory> unit_history;  // ReportOptions::unit_history
};

}  // namespace hrgbench::report::internal
