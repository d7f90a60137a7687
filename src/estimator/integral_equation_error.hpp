#pragma once
// Internal entry point of the integral equation-error estimator (see integral_equation_error.cpp).

#include <Eigen/Core>
#include <array>
#include <vector>

#include "hrgbench/estimator/parameters.hpp"
#include "hrgbench/estimator/run_data.hpp"

namespace hrgbench::estimator::internal {

struct IntegralEquationResult {
  Delta delta = Delta::Zero();
  Xi xi = Xi::Zero();
  Eigen::MatrixXd normal;  // normal matrix of the free unknowns (δ free, then δ2·ξ free)
  bool want_sse = false;   // in: compute sse (one more pass over the data)
  double sse = 0.0;        // Σ of squared equation residuals (NaN unless want_sse)
  std::size_t equations = 0;
};

// The per-run sample sums of the regression, which depend on the data and on the ξ held in the
// equations (the fixed ξ, with the free ones at 0), not on which unknowns are free: two solves with
// different free sets and the same held ξ share them instead of passing over the data again. Filled
// on first use; reused while `xi_removed` and the number of runs match.
struct IntegralEquationSums {
  Xi xi_removed = Xi::Constant(kNaN);
  std::vector<Eigen::Matrix<double, 10, 10>> normals;
  std::vector<Eigen::Matrix<double, 10, 1>> rhss;
};

// False when the regression is singular. `threads` as in OutputErrorProblem (resolved already).
bool IntegralEquationError(const std::vector<RunData>& runs, const std::array<bool, 6>& delta_free,
                           const Delta& delta_fixed, const XiMask& xi_free, const Xi& xi_fixed,
                           IntegralEquationResult* out, int threads = 1,
                           IntegralEquationSums* sums = nullptr);

}  // namespace hrgbench::estimator::internal
