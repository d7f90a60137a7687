#pragma once
// A converged ML summary of two in-model runs (delta, xi and their std written by hand, no
// estimator run) and a limits file it meets: the synthetic unit the verdict's and the judge's tests
// share.

#include <gtest/gtest.h>

#include "hrgbench/config/limits_config.hpp"
#include "hrgbench/estimator/summary.hpp"

namespace hrgbench::testing {

inline estimator::EstimateSummary InModelUnit() {
  estimator::EstimateSummary s;
  s.method = "ml";
  s.termination = estimator::Termination::kConverged;
  s.message = "converged";
  s.delta << -0.001, 0.3, 1e-7, -2e-7, 3e-7, 0.0;
  s.delta_std = estimator::Delta::Constant(1e-6);
  s.delta_estimated = {true, true, true, true, true, true};
  s.xi << 0.01, 0.0, 0.0, 0.0;
  s.xi_std = estimator::Xi::Constant(1e-5);
  s.xi_estimated = estimator::kAllXi;
  s.residual_rms = 1.0e-4;
  s.noise_sigma = 1.0e-4;
  // Two runs of 100 000 samples, in model: ratio 1.001, white residuals, Ω as recorded.
  for (int run = 1; run <= 2; ++run) {
    estimator::RunFitDiagnostics d;
    d.run_id = run;
    d.samples = 100000;
    d.noise_sigma = 1.0e-4;
    d.residual_rms = 1.001e-4;
    d.residual_ratio = 1.001;
    d.whiteness_z = 0.4;
    d.omega_offset_in_std = -0.7;
    s.diagnostics.runs.push_back(d);
  }
  return s;
}

inline bench::LimitsConfig ExampleLimits() {
  auto limits = bench::ParseLimitsConfig(
      "[limits]\nname = \"t\"\ndelta1 = [-0.002, -0.0005]\ndelta2 = [0.29, 0.31]\n"
      "xi1 = [-0.02, 0.02]\nresidual_rms = [0.0, 5e-4]\n",
      "l.toml");
  EXPECT_TRUE(limits.has_value());
  return *limits;
}

}  // namespace hrgbench::testing
