// The integral equation-error estimator: the starting point of maximum likelihood, and a method of
// its own. Integrating dz/dt = 2·Mδ(Ω, z)·δ from the first sample gives
//   r(t_k) − r(t_0) = 2·Mδ(Ω, ∫ r dt)·δ,
// linear in δ with no numerical derivative (the trapezoid integral smooths the noise instead of
// amplifying it). The distortion ξ enters to first order as Ω-proportional anisotropies,
// (δ3, δ4, δ5, δ6)_eff = (δ3 − 4Ωδ2ξ4, δ4 + 4Ωδ2ξ1, δ5 + 4Ωδ2ξ3, δ6 − 4Ωδ2ξ2), so one extra column
// Ω·Mδ[:, j] per estimated ξ gives ξ from its coefficient. ξ held fixed is removed exactly first.
#include "integral_equation_error.hpp"

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

// Unpacks the solution: δ directly, ξ from the products δ2·ξ.
bool FinishSolution(const std::vector<int>& columns, const Eigen::VectorXd& solution,
                    const Delta& delta_fixed, const Xi& xi_fixed, const Eigen::MatrixXd& normal,
                    IntegralEquationResult* out) {
  out->delta = delta_fixed;
  out->xi = xi_fixed;
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
      out->xi[k] = std::abs(delta2) > 1e-12 ? xi_products[k] / delta2 : 0.0;
  out->normal = normal;
  return true;
}

bool IntegralEquationError(const std::vector<RunData>& runs, const std::array<bool, 6>& delta_free,
                           const Delta& delta_fixed, const XiMask& xi_free, const Xi& xi_fixed,
                           IntegralEquationResult* out, int threads, IntegralEquationSums* sums) {
  // Unknowns: the free δ, then δ2·ξk for each free ξ (linear, unlike ξ itself).
  std::vector<int> columns;  // 0..5 δ, 6..9 ξ
  for (int j = 0; j < 6; ++j)
    if (delta_free[j]) columns.push_back(j);
  for (int k = 0; k < 4; ++k)
    if (xi_free[k]) columns.push_back(6 + k);
  const auto n = static_cast<Eigen::Index>(columns.size());
  Xi xi_removed = xi_fixed;
  for (int k = 0; k < 4; ++k)
    if (xi_free[k]) xi_removed[k] = 0.0;

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
  const bool reuse = cache.normals.size() == runs.size() && cache.xi_removed == xi_removed;
  if (!reuse) {
    cache.xi_removed = xi_removed;
    cache.normals.assign(runs.size(), Normal::Zero());
    cache.rhss.assign(runs.size(), Rhs::Zero());
  }
  std::vector<Normal>& normals = cache.normals;
  std::vector<Rhs>& rhss = cache.rhss;
  const auto accumulate = [&](std::size_t r) {
    Eigen::Matrix<double, 6, 6> mm = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> ml = Eigen::Matrix<double, 6, 1>::Zero();
    // lazyProduct: products this small are faster unrolled than through Eigen's blocked GEMM.
    ForEachEquation(runs[r], xi_removed, [&](const Forms& lhs, const Matrix46& m) {
      mm.noalias() += m.transpose().lazyProduct(m);
      ml.noalias() += m.transpose().lazyProduct(lhs);
    });
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
  if (!out->want_sse) return FinishSolution(columns, solution, delta_fixed, xi_fixed, normal, out);
  out->sse = 0.0;
  Eigen::Matrix<double, 4, Eigen::Dynamic> row_block(4, n);
  for (const RunData& run : runs) {
    ForEachEquation(run, xi_removed, [&](Forms lhs, const Matrix46& m) {
      fill(run.omega_rad_s, m, &lhs, &row_block);
      out->sse += (lhs - row_block.lazyProduct(solution)).squaredNorm();
    });
  }
  return FinishSolution(columns, solution, delta_fixed, xi_fixed, normal, out);
}

}  // namespace internal
}  // namespace hrgbench::estimator
