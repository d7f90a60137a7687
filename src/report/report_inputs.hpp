#pragma once
// What the page, the figures and the data block are made from: the session as read, the runs that
// could be loaded, the estimate drawn (the record's, or a re-run) and each run's fitted model.
// Internal to src/report.

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
#include "hrgbench/session/session_record.hpp"

namespace hrgbench::report::internal {

// One entry of session.json "runs", and what became of it.
struct RunView {
  int id = 0;
  std::size_t index = 0;    // position in session.json "runs" (for JSON pointers)
  std::string status;       // runs[].status as recorded
  std::string file;         // runs[].file
  bool loaded = false;      // its samples could be read (they are in `data` only while its
                            // part of the page is made: session_report.cpp)
  std::size_t samples = 0;  // samples read (when loaded), and their first and last t_s
  double first_t_s = 0.0, last_t_s = 0.0;
  // Its seven figures are drawn (ReportOptions::max_runs_with_figures chooses which runs).
  bool figures = true;
  std::string not_loaded_reason;  // why not (status, missing file, empty, unreadable)
  estimator::RunData data;        // id, Ω, t_s, y (when loaded)
  // The run CSV's temp_c and freq_hz columns (the electronics' last status at each sample),
  // parallel to data.t_s; empty when the CSV has none (and dropped with the samples).
  std::vector<double> temperature_c;
  std::vector<double> resonant_frequency_hz;
  // The fitted model at data.t_s (empty when the estimate has no entry for this run).
  estimator::RunChannels fitted_y;
  estimator::RunChannels fitted_x;
};

struct ReportInputs {
  std::filesystem::path session_dir;
  // session.json as read by its one reader: the page takes every recorded value from its fields,
  // and builds each value's data-source pointer from the key names (page_pointer.hpp).
  session::SessionRecord record;
  double sample_rate_hz = 0.0;  // the session's (session::Session::sample_rate_hz)
  std::vector<RunView> runs;
  // The estimate drawn: the estimate of record as a summary (δ, ξ, std, σ̂, each run's nuisance;
  // session_report.cpp RecordedSummary), or a re-run (method ml) when asked or when the record
  // keeps no fitted runs. nullopt when there is none.
  std::optional<estimator::EstimateSummary> summary;
  // outcome.estimate as recorded, or EstimateReportJson of the re-run (null when none).
  nlohmann::json estimate_json;
  // Warnings, each once, in the order found: the session reader's, the recorded estimate's, the
  // re-run's, the report's own.
  std::vector<std::string> warnings;
  std::optional<UnitHistory> unit_history;  // ReportOptions::unit_history
  // <session>/tune.json as read (tune_data.hpp), when the unit was tuned.
  std::optional<nlohmann::json> tune;
  PaperSize paper = PaperSize::kA4;  // ReportOptions::paper
};

}  // namespace hrgbench::report::internal
