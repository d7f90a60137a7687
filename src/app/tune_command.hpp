#pragma once
// `hrg-bench tune DIR`: a unit's closed PASS session made into its compensation, written to its
// electronics, refined on the table and verified (bench/tuning/tune_unit.hpp); DIR/tune.json
// records it. The station is the one the session ran on (its saved config). The session's report
// is then made again with its tuning section (report/tune_data.hpp), as `report` says.
//
// Exit codes (session/exit_codes.hpp), the tuning's verdict (bench/tuning/tune_verdict.hpp):
// 0 PASS; 1 FAIL (a rate error that did not fall to its bound, a [tune] limit not met); 2 ERROR
// (a step that did not finish, residuals the prediction does not explain, a limit not judged);
// 3 ABORTED (Ctrl-C); 4 the folder or an option.

#include <atomic>
#include <filesystem>
#include <string>
#include <vector>

#include "app/report_job.hpp"
#include "hrgbench/config/bench_configs.hpp"

namespace hrgbench::app {

struct TuneOptions {
  std::filesystem::path dir;
  std::vector<double> rates_rad_s = {0.3, -0.3};
  double verify_turns = 2.0;
  double refine_turns = 8.0;
  unsigned sample_rate_hz = 1000;
  double zero_rate_hold_s = 0.0;  // > 0: the Allan deviation of a zero-rate hold this long
  bool json = false;
  // Ctrl-C: the count of interrupts (non-zero: stop safely) — the program's handler's counter.
  const std::atomic<int>* interrupts = nullptr;
  ReportMode report = ReportMode::kWait;  // the session's report, remade with the tuning
};

int Tune(const TuneOptions& options);

// The closed session `dir`'s report (with its tuning section when it has tune.json), made as `mode`
// says with the station's store and paper. Its report.html, or empty when none is made.
std::string ReportTunedSession(const std::filesystem::path& dir, const bench::BenchConfigs& configs,
                               ReportMode mode);

}  // namespace hrgbench::app
