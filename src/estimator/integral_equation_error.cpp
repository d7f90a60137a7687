// The integral equation-error estimator: the starting point of maximum likelihood, and a method of
// its own. Integrating dz/dt = 2·Mδ(Ω, z)·δ from the first sample gives
//   r(t_k) − r(t_0) = 2·Mδ(Ω, ∫ r dt)·δ,
// linear in δ with no numerical derivative (the trapezoid integral smooths the noise instead of
// amplifying it). The distortion ξ enters to first order as Ω-proportional anisotropies,
// (δ3, δ4, δ5, δ6)_eff = (δ3 − 4Ωδ2ξ4, δ4 + 4Ωδ2ξ1, δ5 + 4Ωδ2ξ3, δ6 − 4Ωδ2ξ2), so one extra column
// Ω·Mδ[:, j] per estimated ξ gives ξ from its coefficient. ξ held fixed is removed exactly first.
#include "integral_equation_error.hpp"

#include <cmath>
#include <complex>

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

// The equations of ML's start (IntegralEquationResult::initial_forms_free), visit(lhs, m) for
// t_1 … t_{n−2}: lhs = r(t_k) − r(t_0), m = 2·Mδ(Ω, I_k) with I_k the trapezoid integral corrected
// at its ends (Euler–Maclaurin: −h²/12·(r'(t_k) − r'(t_1)), per interval for uneven steps, r' by
// three-point differences, hence one sample of delay and no equation at the last sample). Why: the
// trapezoid integral of a form turning at the pattern's rate ω is off by ≈ (ω·h)²/12 relative,
// along ω itself, so δ2 came out high by that much (1.2e-4 relative at 20 samples/s on the
// production design's rates) whatever the run's length: in units of the fit's std, ever further
// off as runs get longer. Corrected, the error is O((ω·h)⁴). The correction's constant term, and
// r(t_0)'s noise, are absorbed by the run's unknown initial forms.
template <typename Visit>
void ForEachStartEquation(const RunData& run, const Xi& xi_removed, Visit visit) {
  // (I + C)⁻¹ on u = (x1 + i·x2, x3 + i·x4), as in UndistortExact but inverted once per run: the
  // start removes the first solve's ξ from every sample, and two complex divisions per sample
  // would cost as much as the regression's products.
  using Complex = std::complex<double>;
  const bool undistort = (xi_removed.array() != 0.0).any();
  const Complex p(xi_removed[0], -xi_removed[1]), q(xi_removed[3], -xi_removed[2]);
  const Complex inverse_det = 1.0 / ((1.0 + p) * (1.0 - p) - q * q);
  const Complex g11 = (1.0 - p) * inverse_det, g12 = -q * inverse_det,
                g22 = (1.0 + p) * inverse_det;
  const auto forms = [&](Eigen::Index k) {
    if (!undistort) return QuadraticForms(run.y.col(k));
    const Complex v1(run.y(0, k), run.y(1, k)), v2(run.y(2, k), run.y(3, k));
    const Complex u1 = g11 * v1 + g12 * v2, u2 = g12 * v1 + g22 * v2;
    return QuadraticForms(State(u1.real(), u1.imag(), u2.real(), u2.imag()));
  };
  const Eigen::Index n = run.size();
  if (n < 3) return;
  const Forms r0 = forms(0);
  // r at t_{k−1}, t_k, t_{k+1}; the derivative at t_{k−1}; the trapezoid integral to t_k and its
  // correction so far.
  Forms before = r0, now = forms(1);
  Forms derivative_before = Forms::Zero();
  Forms integral = 0.5 * (run.t_s[1] - run.t_s[0]) * (now + before);
  Forms correction = Forms::Zero();
  for (Eigen::Index k = 1; k + 1 < n; ++k) {
    const Forms after = forms(k + 1);
    const double a = run.t_s[k] - run.t_s[k - 1], b = run.t_s[k + 1] - run.t_s[k];
    const Forms derivative = (a * a * (after - now) + b * b * (now - before)) / (a * b * (a + b));
    if (k >= 2) correction -= (a * a / 12.0) * (derivative - derivative_before);
    visit(Forms(now - r0),
          Matrix46(2.0 * FormsRegressor(run.omega_rad_s, Forms(integral + correction))));
    integral += 0.5 * b * (after + now);
    derivative_before = derivative;
    before = now;
    now = after;
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

bool IntegralEquationError(const std::vector<RunData>& runs, const std::array<bool, 6>& delta_free,
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
  const bool reuse = cache.normals.size() == runs.size() && cache.xi_removed == xi_removed &&
                     cache.initial_forms_free == forms_free;
  if (!reuse) {
    cache.xi_removed = xi_removed;
    cache.initial_forms_free = forms_free;
    cache.normals.assign(runs.size(), Normal::Zero());
    cache.rhss.assign(runs.size(), Rhs::Zero());
  }
  std::vector<Normal>& normals = cache.normals;
  std::vector<Rhs>& rhss = cache.rhss;
  const auto accumulate = [&](std::size_t r) {
    Eigen::Matrix<double, 6, 6> mm = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> ml = Eigen::Matrix<double, 6, 1>::Zero();
    // lazyProduct: products this small are faster unrolled than through Eigen's blocked GEMM.
    // With the initial forms c unknown, their columns are the identity in every equation: they
    // are eliminated per run from the sums of m and lhs (a Schur complement: the regression on
    // m and lhs centred on their run means).
    Matrix46 m_sum = Matrix46::Zero();
    Forms lhs_sum = Forms::Zero();
    double count = 0.0;
    if (forms_free) {
      ForEachStartEquation(runs[r], xi_removed, [&](const Forms& lhs, const Matrix46& m) {
        mm.noalias() += m.transpose().lazyProduct(m);
        ml.noalias() += m.transpose().lazyProduct(lhs);
        m_sum += m;
        lhs_sum += lhs;
        count += 1.0;
      });
    } else {
      ForEachEquation(runs[r], xi_removed, [&](const Forms& lhs, const Matrix46& m) {
        mm.noalias() += m.transpose().lazyProduct(m);
        ml.noalias() += m.transpose().lazyProduct(lhs);
      });
    }
    if (forms_free && count > 0.0) {
      mm.noalias() -= m_sum.transpose().lazyProduct(m_sum) / count;
      ml.noalias() -= m_sum.transpose().lazyProduct(lhs_sum) / count;
    }
    Eigen::Matrix<double, 6, 10> select = Eigen::Matrix<double, 6, 10>::Zero();
    select.leftCols<6>().setIdentity();
    for (int k = 0; k < 4; ++k)
      select(kXiColumn[static_cast<std::size_t>(k)], 6 + k) =
          4.0 * runs[r].omega_rad_s * kXiSign[static_cast<std::size_t>(k)];
    normals[r] = select.transpose() * mm * select;
    rhss[r] = select.transpose() * ml;
  };
  if (!reuse) ParallelFor(runs.size(), threads, accumulate);
  Normal full_normal = Normal::Zero();
  Rhs full_rhs = Rhs::Zero();
  out->equations = 0;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    full_normal += normals[r];
    full_rhs += rhss[r];
    out->equations += static_cast<std::size_t>(std::max<Eigen::Index>(0, runs[r].size() - 1));
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
  for (const RunData& run : runs) {
    ForEachEquation(run, xi_removed, [&](Forms lhs, const Matrix46& m) {
      fill(run.omega_rad_s, m, &lhs, &row_block);
      out->sse += (lhs - row_block.lazyProduct(solution)).squaredNorm();
    });
  }
  return FinishSolution(columns, solution, delta_fixed, xi_removed, normal, out);
}

bool RefinedIntegralEquationError(const std::vector<RunData>& runs,
                                  const std::array<bool, 6>& delta_free, const Delta& delta_fixed,
                                  const XiMask& xi_free, const IntegralEquationResult& first,
                                  IntegralEquationResult* out, int threads,
                                  IntegralEquationSums* sums) {
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
