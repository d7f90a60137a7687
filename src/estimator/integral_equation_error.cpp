// The integral equation-error estimator: the starting point of maximum likelihood, and a method of
// its own. Integrating dz/dt = 2·Mδ(Ω, z)·δ from the first sample gives
//   r(t_k) − r(t_0) = 2·Mδ(Ω, ∫ r dt)·δ,
// linear in δ with no numerical derivative (the trapezoid integral smooths the noise instead of
// amplifying it). The distortion ξ enters to first order as Ω-proportional anisotropies,
// (δ3, δ4, δ5, δ6)_eff = (δ3 − 4Ωδ2ξ4, δ4 + 4Ωδ2ξ1, δ5 + 4Ωδ2ξ3, δ6 − 4Ωδ2ξ2), so one extra column
// Ω·Mδ[:, j] per estimated ξ gives ξ from its coefficient. ξ held fixed is removed exactly first.
#include "integral_equation_error.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/model.hpp"
#include "least_squares_util.hpp"
#include "parallel_for.hpp"

namespace hrgbench::estimator {
namespace internal {
namespace {

// The Mδ column each ξ shows up in, and the sign of 4Ωδ2ξ in it.
constexpr std::array<int, 4> kXiColumn = {kDampingAnisotropySin, kFrequencyAnisotropySin,
                                          kFrequencyAnisotropyCos, kDampingAnisotropyCos};
constexpr std::array<double, 4> kXiSign = {+1.0, -1.0, +1.0, -1.0};

}  // namespace

// Calls visit(lhs, m) for every equation lhs = r(t_k) − r(t_0) = m·δ (m = 2·Mδ(Ω, ∫r dt)) of a run.
template <typename Visit>
void ForEachEquation(const RunData& run, const Xi& xi_removed, Visit visit) {
  // With no ξ to remove (every ξ estimated, or held at 0) the undistortion is the identity: two
  // complex divisions per sample saved, and the same values (division by exactly 1).
  const bool undistort = (xi_removed.array() != 0.0).any();
  const auto forms = [&](Eigen::Index k) {
    return undistort ? QuadraticForms(UndistortExact(xi_removed, run.y.col(k)))
                     : QuadraticForms(run.y.col(k));
  };
  const Forms r0 = forms(0);
  Forms previous = r0;
  Forms integral = Forms::Zero();
  for (Eigen::Index k = 1; k < run.size(); ++k) {
    const Forms rk = forms(k);
    integral += 0.5 * (run.t_s[k] - run.t_s[k - 1]) * (rk + previous);
    previous = rk;
    visit(Forms(rk - r0), Matrix46(2.0 * FormsRegressor(run.omega_rad_s, integral)));
  }
}

// The quadratic monomials of a sample, y_a·y_b for a ≤ b: every quadratic form of (I + C)⁻¹·y, for
// any ξ, is a fixed combination of them (FormsOfMonomials).
using Monomials = Eigen::Matrix<double, 10, 1>;
constexpr std::array<std::array<int, 2>, 10> kMonomialPairs = {
    {{0, 0}, {1, 1}, {2, 2}, {3, 3}, {0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};

Monomials MonomialsOf(const RunData& run, Eigen::Index k) {
  Monomials q;
  for (std::size_t i = 0; i < kMonomialPairs.size(); ++i)
    q[static_cast<Eigen::Index>(i)] =
        run.y(kMonomialPairs[i][0], k) * run.y(kMonomialPairs[i][1], k);
  return q;
}

// The forms (Ac, As, K, S) of x = (I + C(ξ))⁻¹·y as a 4×10 matrix on the monomials of y: each
// form is a quadratic form of y, read off QuadraticForms by polarisation (a monomial y_a² has the
// form's value at h·e_a, y_a·y_b the excess at h·(e_a + e_b)), with h = (I +
// DistortionMatrix(ξ))⁻¹, so the forms and the pick-off are defined once, in model.cpp.
Eigen::Matrix<double, 4, 10> FormsOfMonomials(const Xi& xi) {
  const Matrix4 h = (Matrix4::Identity() + DistortionMatrix(xi)).inverse();
  Eigen::Matrix<double, 4, 10> l;
  for (std::size_t c = 0; c < kMonomialPairs.size(); ++c) {
    const int a = kMonomialPairs[c][0], b = kMonomialPairs[c][1];
    const Forms column = a == b ? QuadraticForms(h.col(a))
                                : Forms(QuadraticForms(h.col(a) + h.col(b)) -
                                        QuadraticForms(h.col(a)) - QuadraticForms(h.col(b)));
    l.col(static_cast<Eigen::Index>(c)) = column;
  }
  return l;
}

// The longest block of equations StartMonomialSums averages, in time and in samples.
constexpr double kStartBlockS = 0.008;
constexpr Eigen::Index kStartBlockSamples = 8;

// ML's start (IntegralEquationResult::initial_forms_free): the sums over t_1 … t_{n−2} of the
// monomials' end-corrected integral I_k and of q(t_k) − q(t_0), and their products. The integral is
// the trapezoid's corrected at its ends (Euler–Maclaurin: −h²/12·(q'(t_k) − q'(t_1)), per interval
// for uneven steps, q' by three-point differences, hence one sample of delay and no equation at the
// last sample). Why: the trapezoid integral of a form turning at the pattern's rate ω is off by
// ≈ (ω·h)²/12 relative, along ω itself, so δ2 came out high by that much (1.2e-4 relative at 20
// samples/s on the production design's rates) whatever the run's length: in units of the fit's
// std, ever further off as runs get longer. Corrected, the error is O((ω·h)⁴). The correction's
// constant term, and q(t_0)'s noise, are absorbed by the run's unknown initial forms. On the
// monomials rather than the forms, so that one pass serves every ξ removed (both candidates and the
// refinement), each solve then costing a few 10×10 products per run.
//
// The equations enter as their means over blocks of consecutive samples (kStartBlockS long, at
// most kStartBlockSamples): the regression is linear in I_k, so a block's mean equation is exact,
// Δq̄ = m(Ī)·δ, and its noise is the mean's, weighted by the block's count. What is lost is the
// spread of I_k within a block, a fraction ≈ (ω·T)²/12 of the information (2e-4 for forms turning
// at 6 rad/s, T = 8 ms): the start does not need it, and the 155 products per equation, most of
// this pass, are made once per block.
IntegralEquationSums::Monomial StartMonomialSums(const RunData& run) {
  IntegralEquationSums::Monomial sums;
  sums.integral_integral.setZero();
  sums.integral_lhs.setZero();
  sums.integral.setZero();
  sums.lhs.setZero();
  sums.count = 0.0;
  const Eigen::Index n = run.size();
  if (n < 3) return sums;
  const Monomials q0 = MonomialsOf(run, 0);
  // q at t_{k−1}, t_k, t_{k+1}; the derivative at t_{k−1}; the trapezoid integral to t_k and its
  // correction so far.
  Monomials before = q0, now = MonomialsOf(run, 1);
  Monomials derivative_before = Monomials::Zero();
  Monomials integral = 0.5 * (run.t_s[1] - run.t_s[0]) * (now + before);
  Monomials correction = Monomials::Zero();
  const double mean_step_s =
      (run.t_s[static_cast<std::size_t>(n - 1)] - run.t_s[0]) / static_cast<double>(n - 1);
  const Eigen::Index block = std::clamp<Eigen::Index>(
      mean_step_s > 0.0 ? static_cast<Eigen::Index>(kStartBlockS / mean_step_s) : 1, 1,
      kStartBlockSamples);
  Monomials block_integral = Monomials::Zero(), block_lhs = Monomials::Zero();
  Eigen::Index in_block = 0;
  for (Eigen::Index k = 1; k + 1 < n; ++k) {
    const Monomials after = MonomialsOf(run, k + 1);
    const double a = run.t_s[k] - run.t_s[k - 1], b = run.t_s[k + 1] - run.t_s[k];
    const double scale = 1.0 / (a * b * (a + b));
    const Monomials derivative = (a * a * scale) * (after - now) + (b * b * scale) * (now - before);
    if (k >= 2) correction -= (a * a / 12.0) * (derivative - derivative_before);
    block_integral += integral + correction;
    block_lhs += now - q0;
    if (++in_block == block || k + 2 == n) {
      // The block's mean equation, weighted by its count: Σ I·Iᵀ/c from the block's sums.
      const double weight = 1.0 / static_cast<double>(in_block);
      const Monomials i_mean = weight * block_integral;
      // The upper triangle only (symmetric: filled in below).
      for (Eigen::Index c = 0; c < 10; ++c)
        for (Eigen::Index r = 0; r <= c; ++r)
          sums.integral_integral(r, c) += i_mean[r] * block_integral[c];
      sums.integral_lhs.noalias() += i_mean.lazyProduct(block_lhs.transpose());
      sums.integral += block_integral;
      sums.lhs += block_lhs;
      sums.count += static_cast<double>(in_block);
      block_integral.setZero();
      block_lhs.setZero();
      in_block = 0;
    }
    integral += 0.5 * b * (after + now);
    derivative_before = derivative;
    before = now;
    now = after;
  }
  sums.integral_integral.triangularView<Eigen::StrictlyLower>() =
      sums.integral_integral.transpose();
  return sums;
}

// The 6×6 Σmᵀm and Σmᵀ·lhs of a run's start equations with ξ removed (forms = l·monomials),
// each run's initial forms eliminated: m = 2·Mδ(Ω, l·I_k) = Σ_j (l·I_k)_j·B_j is linear in the
// forms, so both follow from the monomial sums.
void StartNormalEquations(const IntegralEquationSums::Monomial& sums, double omega_rad_s,
                          const Eigen::Matrix<double, 4, 10>& l, Eigen::Matrix<double, 6, 6>* mm,
                          Eigen::Matrix<double, 6, 1>* ml) {
  std::array<Matrix46, 4> basis;
  for (int j = 0; j < 4; ++j)
    basis[static_cast<std::size_t>(j)] = 2.0 * FormsRegressor(omega_rad_s, Forms::Unit(j));
  const Matrix4 uu = l * sums.integral_integral * l.transpose();         // Σ u·uᵀ, u = l·I_k
  const Matrix4 vu = l * sums.integral_lhs.transpose() * l.transpose();  // Σ v·uᵀ, v = l·Δq
  const Forms u_sum = l * sums.integral, v_sum = l * sums.lhs;
  mm->setZero();
  ml->setZero();
  Matrix46 m_sum = Matrix46::Zero();
  for (int j = 0; j < 4; ++j) {
    const Matrix46& bj = basis[static_cast<std::size_t>(j)];
    for (int i = 0; i < 4; ++i)
      *mm += uu(j, i) * bj.transpose() * basis[static_cast<std::size_t>(i)];
    *ml += bj.transpose() * vu.col(j);
    m_sum += u_sum[j] * bj;
  }
  if (sums.count > 0.0) {
    *mm -= m_sum.transpose() * m_sum / sums.count;
    *ml -= m_sum.transpose() * v_sum / sums.count;
  }
}

// Unpacks the solution: δ directly, ξ from the products δ2·ξ.
// `xi_base`: the ξ removed from the data (held ξ at their values; free ξ at 0, or where a first
// solve put them), to which the free ξ's solved corrections are added.
bool FinishSolution(const std::vector<int>& columns, const Eigen::VectorXd& solution,
                    const Delta& delta_fixed, const Xi& xi_base, const Eigen::MatrixXd& normal,
                    IntegralEquationResult* out) {
  out->delta = delta_fixed;
  out->xi = xi_base;
  Xi xi_products = Xi::Zero();  // δ2·ξk
  XiMask xi_free = kNoXi;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const int which = columns[c];
    const auto i = static_cast<Eigen::Index>(c);
    if (which < 6) {
      out->delta[which] = solution[i];
    } else {
      xi_products[which - 6] = solution[i];
      xi_free[static_cast<std::size_t>(which - 6)] = true;
    }
  }
  const double delta2 = out->delta[kScaleFactor];
  for (int k = 0; k < 4; ++k)
    if (xi_free[static_cast<std::size_t>(k)])
      out->xi[k] += std::abs(delta2) > 1e-12 ? xi_products[k] / delta2 : 0.0;
  out->normal = normal;
  return true;
}

bool IntegralEquationError(const RunSet& runs, const std::array<bool, 6>& delta_free,
                           const Delta& delta_fixed, const XiMask& xi_free, const Xi& xi_fixed,
                           IntegralEquationResult* out, int threads, IntegralEquationSums* sums,
                           const Xi* xi_free_around) {
  // Unknowns: the free δ, then δ2·ξk for each free ξ (linear, unlike ξ itself).
  std::vector<int> columns;  // 0..5 δ, 6..9 ξ
  for (int j = 0; j < 6; ++j)
    if (delta_free[j]) columns.push_back(j);
  for (int k = 0; k < 4; ++k)
    if (xi_free[k]) columns.push_back(6 + k);
  const auto n = static_cast<Eigen::Index>(columns.size());
  Xi xi_removed = xi_fixed;
  for (int k = 0; k < 4; ++k)
    if (xi_free[k]) xi_removed[k] = xi_free_around != nullptr ? (*xi_free_around)[k] : 0.0;

  const auto fill = [&](double omega, const Matrix46& m, Forms* lhs,
                        Eigen::Matrix<double, 4, Eigen::Dynamic>* row_block) {
    for (int j = 0; j < 6; ++j)
      if (!delta_free[j]) *lhs -= m.col(j) * delta_fixed[j];
    for (Eigen::Index c = 0; c < n; ++c) {
      const auto which = static_cast<std::size_t>(columns[static_cast<std::size_t>(c)]);
      row_block->col(c) =
          which < 6 ? Forms(m.col(static_cast<Eigen::Index>(which)))
                    : Forms(m.col(kXiColumn[which - 6]) * (4.0 * omega * kXiSign[which - 6]));
    }
  };

  // Runs are independent: one normal system per run, summed after. Every column is a column of m
  // (δ1…δ6) or one scaled by the run's constant 4Ω·sign (δ2·ξ1…δ2·ξ4), so the block of all ten is
  // m·S with S (6×10) constant over a run: the samples accumulate the 6×6 mᵀm and mᵀ·lhs only, and
  // SᵀmᵀmS follows once per run. The free columns are taken out afterwards, the held δ moved to the
  // right-hand side (b_F − N_FH·δ_H): the same normal equations as regressing on the free columns
  // alone.
  using Normal = Eigen::Matrix<double, 10, 10>;
  using Rhs = Eigen::Matrix<double, 10, 1>;
  IntegralEquationSums local;
  IntegralEquationSums& cache = sums != nullptr ? *sums : local;
  const bool forms_free = out->initial_forms_free;
  // ML's start: the monomial sums serve any ξ removed (StartMonomialSums); the normal equations
  // follow from them per run, every time.
  const bool reuse = !forms_free && cache.normals.size() == runs.size() &&
                     cache.xi_removed == xi_removed && !cache.initial_forms_free;
  if (!reuse) {
    cache.xi_removed = xi_removed;
    cache.initial_forms_free = forms_free;
    cache.normals.assign(runs.size(), Normal::Zero());
    cache.rhss.assign(runs.size(), Rhs::Zero());
  }
  std::vector<Normal>& normals = cache.normals;
  std::vector<Rhs>& rhss = cache.rhss;
  const auto select = [&](std::size_t r) {
    Eigen::Matrix<double, 6, 10> s = Eigen::Matrix<double, 6, 10>::Zero();
    s.leftCols<6>().setIdentity();
    for (int k = 0; k < 4; ++k)
      s(kXiColumn[static_cast<std::size_t>(k)], 6 + k) =
          4.0 * runs.Info(r).omega_rad_s * kXiSign[static_cast<std::size_t>(k)];
    return s;
  };
  const auto accumulate = [&](std::size_t r) {
    Eigen::Matrix<double, 6, 6> mm = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> ml = Eigen::Matrix<double, 6, 1>::Zero();
    // lazyProduct: products this small are faster unrolled than through Eigen's blocked GEMM.
    ForEachEquation(*runs.Load(r), xi_removed, [&](const Forms& lhs, const Matrix46& m) {
      mm.noalias() += m.transpose().lazyProduct(m);
      ml.noalias() += m.transpose().lazyProduct(lhs);
    });
    const Eigen::Matrix<double, 6, 10> sel = select(r);
    normals[r] = sel.transpose() * mm * sel;
    rhss[r] = sel.transpose() * ml;
  };
  if (forms_free) {
    if (cache.monomials.size() != runs.size()) {
      cache.monomials.assign(runs.size(), IntegralEquationSums::Monomial());
      ParallelFor(runs.size(), threads,
                  [&](std::size_t r) { cache.monomials[r] = StartMonomialSums(*runs.Load(r)); });
    }
    const Eigen::Matrix<double, 4, 10> l = FormsOfMonomials(xi_removed);
    for (std::size_t r = 0; r < runs.size(); ++r) {
      Eigen::Matrix<double, 6, 6> mm;
      Eigen::Matrix<double, 6, 1> ml;
      StartNormalEquations(cache.monomials[r], runs.Info(r).omega_rad_s, l, &mm, &ml);
      const Eigen::Matrix<double, 6, 10> sel = select(r);
      normals[r] = sel.transpose() * mm * sel;
      rhss[r] = sel.transpose() * ml;
    }
  }
  if (!reuse && !forms_free) ParallelFor(runs.size(), threads, accumulate);
  Normal full_normal = Normal::Zero();
  Rhs full_rhs = Rhs::Zero();
  out->equations = 0;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    full_normal += normals[r];
    full_rhs += rhss[r];
    out->equations += static_cast<std::size_t>(std::max<Eigen::Index>(0, runs.Info(r).samples - 1));
  }
  Eigen::MatrixXd normal(n, n);
  Eigen::VectorXd rhs(n);
  for (Eigen::Index a = 0; a < n; ++a) {
    const int ca = columns[static_cast<std::size_t>(a)];
    rhs[a] = full_rhs[ca];
    for (int j = 0; j < 6; ++j)
      if (!delta_free[j]) rhs[a] -= full_normal(ca, j) * delta_fixed[j];
    for (Eigen::Index b = 0; b < n; ++b)
      normal(a, b) = full_normal(ca, columns[static_cast<std::size_t>(b)]);
  }
  Eigen::VectorXd solution = Eigen::VectorXd::Zero(n);
  if (n > 0 && !SolveScaledSpd(normal, rhs, &solution)) return false;

  out->sse = kNaN;
  if (!out->want_sse || forms_free)
    return FinishSolution(columns, solution, delta_fixed, xi_removed, normal, out);
  out->sse = 0.0;
  Eigen::Matrix<double, 4, Eigen::Dynamic> row_block(4, n);
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const double omega = runs.Info(r).omega_rad_s;
    ForEachEquation(*runs.Load(r), xi_removed, [&](Forms lhs, const Matrix46& m) {
      fill(omega, m, &lhs, &row_block);
      out->sse += (lhs - row_block.lazyProduct(solution)).squaredNorm();
    });
  }
  return FinishSolution(columns, solution, delta_fixed, xi_removed, normal, out);
}

bool RefinedIntegralEquationError(const RunSet& runs, const std::array<bool, 6>& delta_free,
                                  const Delta& delta_fixed, const XiMask& xi_free,
                                  const IntegralEquationResult& first, IntegralEquationResult* out,
                                  int threads, IntegralEquationSums* sums) {
  // Beyond this the first solve is not near the physical regime (|ξ| ≪ 1) and removing its ξ would
  // only move a stray candidate elsewhere; the output-error cost judges it as it is.
  constexpr double kLargestXiRefined = 0.05;
  bool any_free = false;
  for (int k = 0; k < 4; ++k) {
    if (!xi_free[static_cast<std::size_t>(k)]) continue;
    any_free = true;
    if (!(std::abs(first.xi[k]) <= kLargestXiRefined)) return false;
  }
  if (!any_free) return false;
  IntegralEquationResult refined;
  refined.want_sse = first.want_sse;
  refined.initial_forms_free = first.initial_forms_free;
  if (!IntegralEquationError(runs, delta_free, delta_fixed, xi_free, first.xi, &refined, threads,
                             sums, &first.xi) ||
      !refined.delta.allFinite() || !refined.xi.allFinite())
    return false;
  *out = std::move(refined);
  return true;
}

}  // namespace internal
}  // namespace hrgbench::estimator
