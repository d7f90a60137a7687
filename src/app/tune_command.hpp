#pragma once
// `hrg-bench tune DIR`: a unit's closed PASS session made into its compensation, written to its
// electronics, refined on the table and verified (bench/tuning/tune_unit.hpp); DIR/tune.json
// records it. The station is the one the session ran on (its saved config).
//
// Exit codes (session/exit_codes.hpp), the tuning's verdict (bench/tuning/tune_verdict.hpp):
// 0 PASS; 1 FAIL (a rate error that did not fall to its bound, a [tune] limit not met); 2 ERROR
// (a step that did not finish, residuals the prediction does not explain, a limit not judged);
// 3 ABORTED (Ctrl-C); 4 the folder or an option.

#include <atomic>
#include <filesystem>
#include <vector>

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
};

int Tune(const TuneOptions& options);

}  // namespace hrgbench::app
