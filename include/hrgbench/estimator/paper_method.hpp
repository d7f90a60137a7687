#pragma once
// The paper's estimators (Trutnev, Izmestyev, Shchenyatsky 2025), kept exactly as described as the
// baseline every other method is measured against:
//  - EstimatePaper: ordinary least squares of numerical dz/dt on 2·Mδ(Ω, z), all runs stacked, with
//    z = W(y)·y taken from the raw observation (ξ ignored) and dz/dt from a straight-line fit over
//    `derivative_window` samples, sliding by one sample, regressor at the window centre;
//  - EstimatePaperXiGrid: ξ1 by brute-force grid search, δ re-solved by OLS at every grid point
//  with
//    the first-order special regressor Mδ(Ω, r, λ, 0) (δ2 column corrected), minimising the
//    residual.
// Both are equation-error methods on a numerical derivative: biased under noise and at high rates
// (docs/estimator/model.md); use EstimateMaximumLikelihood for results.

#include <string>
#include <vector>

#include "hrgbench/estimator/run_data.hpp"
#include "hrgbench/estimator/summary.hpp"

namespace hrgbench::estimator {

struct PaperOptions {
  // Samples per straight-line fit; the paper uses 100 at 100 Hz (1 s windows).
  int derivative_window = 100;
  // The paper's ξ1 grid: step 1e-5 on [−0.05, 0.05] (10 001 points).
  double xi1_min = -0.05;
  double xi1_max = 0.05;
  double xi1_step = 1e-5;

  bool IsValid(std::string* why) const;
};

// Minimum samples per run these methods need.
int PaperMinimumSamples(const PaperOptions& options);

EstimateSummary EstimatePaper(const std::vector<RunData>& runs, const PaperOptions& options = {});
EstimateSummary EstimatePaperXiGrid(const std::vector<RunData>& runs,
                                    const PaperOptions& options = {});

}  // namespace hrgbench::estimator
