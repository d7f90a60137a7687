#pragma once
// Internal entry point of the integral equation-error estimator (see integral_equation_error.cpp).

#include <Eigen/Core>
#include <array>
#include <vector>

#include "hrgbench/estimator/parameters.hpp"
#include "hrgbench/estimator/run_data.hpp"
#include "hrgbench/estimator/run_set.hpp"

namespace hrgbench::estimator::internal {

struct IntegralEquationResult {
  Delta delta = Delta::Zero();
  Xi xi = Xi::Zero();
  Eigen::MatrixXd normal;  // normal matrix of the free unknowns (δ free, then δ2·ξ free)
  bool want_sse = false;   // in: compute sse (one more pass over the data; not with the next)
  // in: each run's initial forms are unknowns of the regression (eliminated per run) instead of
  // its first sample's forms: see IntegralEquationError.
  bool initial_forms_free = false;
  double sse = 0.0;  // Σ of squared equation residuals (NaN unless want_sse)
  std::size_t equations = 0;
};

// The per-run sample sums of the regression, which depend on the data and on the ξ held in the
// equations (the fixed ξ, with the free ones at 0), not on which unknowns are free: two solves with
// different free sets and the same held ξ share them instead of passing over the data again. Filled
// on first use; reused while `xi_removed`, `initial_forms_free` and the number of runs match.
// With initial_forms_free, the per-run sums are over the samples' quadratic monomials and serve
// every ξ removed (integral_equation_error.cpp, StartMonomialSums).
struct IntegralEquationSums {
  Xi xi_removed = Xi::Constant(kNaN);
  bool initial_forms_free = false;
  std::vector<Eigen::Matrix<double, 10, 10>> normals;
  std::vector<Eigen::Matrix<double, 10, 1>> rhss;
  struct Monomial {
    Eigen::Matrix<double, 10, 10> integral_integral;  // Σ I_k·I_kᵀ
    Eigen::Matrix<double, 10, 10> integral_lhs;       // Σ I_k·(q(t_k) − q(t_0))ᵀ
    Eigen::Matrix<double, 10, 1> integral;            // Σ I_k
    Eigen::Matrix<double, 10, 1> lhs;                 // Σ (q(t_k) − q(t_0))
    double count = 0.0;
  };
  std::vector<Monomial> monomials;  // filled on first use; the runs must not change after
};

// False when the regression is singular. `threads` as in OutputErrorProblem (resolved already).
// With `out->initial_forms_free` (maximum likelihood's start), the equations are
// r(t_k) = c + 2·Mδ(Ω, I_k)·δ with each run's initial forms c unknown and I_k the trapezoid
// integral corrected at its ends (ForEachStartEquation). Why: with r(t_k) − r(t_0) the first
// sample's noise is in every equation of its run and is absorbed by δ: the start's δ2 was 1e-5…2e-5
// off at σ = 1e-4 on the production design whether the runs lasted 100 or 1000 s (2e-7 and 4e-8
// with c free), so in units of the fit's std, which falls as T^-1.5, it grew with the runs' length
// until Gauss–Newton started outside its quadratic region. `xi_free_around`: when given, the free ξ
// are removed exactly at these values too and the regression's ξ columns are their corrections
// (out->xi = around + correction); see RefinedIntegralEquationError.
bool IntegralEquationError(const RunSet& runs, const std::array<bool, 6>& delta_free,
                           const Delta& delta_fixed, const XiMask& xi_free, const Xi& xi_fixed,
                           IntegralEquationResult* out, int threads = 1,
                           IntegralEquationSums* sums = nullptr,
                           const Xi* xi_free_around = nullptr);

// The integral equation error again with the ξ of a first solve (`first`) removed exactly, so that
// only its small correction is taken to first order. Why: the first-order ξ leaves out terms of
// order |ξ|²·Ω·δ2 in the forms' dynamics that no δ can represent; their effect on the forms is
// secular (it grows with the run's length), and the regression absorbs it into δ2: at |ξ| ≈ 1e-2
// and Ω = 1 rad/s the start's δ2 was 8e-4 off after 1000 s (the pattern's angle 0.9 rad off at the
// run's end, far outside Gauss–Newton's quadratic region, whose width falls as 1/(Ω·T)), against
// 3e-5 after 100 s. With the correction at |Δξ| ~ 1e-4 those terms are ~1e-4 times smaller.
// False (and `out` untouched) when `first` has no free ξ, a ξ too large for the first order to mean
// anything (the weak designs' stray candidates), or a singular regression.
bool RefinedIntegralEquationError(const RunSet& runs, const std::array<bool, 6>& delta_free,
                                  const Delta& delta_fixed, const XiMask& xi_free,
                                  const IntegralEquationResult& first, IntegralEquationResult* out,
                                  int threads = 1, IntegralEquationSums* sums = nullptr);

}  // namespace hrgbench::estimator::internal
