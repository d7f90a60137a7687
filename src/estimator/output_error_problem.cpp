#include "output_error_problem.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <array>

#include "free_run_propagator.hpp"
#include "least_squares_util.hpp"
#include "no_allocation_scope.hpp"
#include "parallel_for.hpp"

namespace hrgbench::estimator::internal {
namespace {

Delta DeltaOf(const FullParameters& p) { return p.head<6>(); }
Xi XiOf(const FullParameters& p) { return p.tail<4>(); }

}  // namespace

FullParameters Pack(const Delta& delta, const Xi& xi) {
  FullParameters p;
  p << delta, xi;
  return p;
}

OutputErrorProblem::OutputErrorProblem(const std::vector<RunData>& runs, std::vector<int> free,
                                       int threads, std::size_t min_samples_for_threads)
    : runs_(runs), free_(std::move(free)) {
  for (const RunData& r : runs_) samples_ += static_cast<std::size_t>(r.size());
  threads_ = samples_ < min_samples_for_threads ? 1 : ResolveThreads(threads, runs_.size());
}

double OutputErrorProblem::Cost(const FullParameters& p, const std::vector<Eigen::Vector4d>& w0,
                                std::vector<double>* per_run) const {
  const CMatrix2 gain = PickoffGain(XiOf(p));
  const CMatrix2 gain_inv = gain.inverse();
  std::vector<double> sums(runs_.size(), 0.0);
  ParallelFor(runs_.size(), threads_, [&](std::size_t r) {
    const RunData& run = runs_[r];
    const FreeRunPropagator propagator(run.omega_rad_s, DeltaOf(p));
    const CVector2 u0 = gain_inv * ToComplex(w0[r]);
    double sum = 0.0;
    const NoAllocationScope no_allocation;
    propagator.ForEachSample(run.t_s, [&](std::size_t k, const PropagatorScalars& s) {
      const CVector2 y = gain * propagator.Propagate(s, u0);
      sum += (run.y.col(static_cast<Eigen::Index>(k)) - ToReal(y)).squaredNorm();
    });
    sums[r] = sum;
  });
  double total = 0.0;
  for (double v : sums) total += v;
  if (per_run) *per_run = std::move(sums);
  return total;
}

// Every Jacobian column, and the model itself, is a combination of five complex functions of time,
//   c = e^{αt}·(f0, f1, t·f0, t·f1, ∂f1/∂μ²),
// with coefficient vectors that are constant over a run (see free_run_propagator.hpp):
//   ŷ      = G·(c0·u0 + c1·B·u0)
//   ∂/∂δ1  = G·(c2·u0 + c3·B·u0)                                  (t·ŷ)
//   ∂/∂δj  = G·(∂μ²/∂δj·(c3/2·u0 + c4·B·u0) + c1·βj·σj·u0)         (j ≥ 2)
//   ∂/∂ξk  = Ck·(c0·u0 + c1·B·u0) − G·(c0·a_k + c1·B·a_k),  a_k = G⁻¹·Ck·u0   (w0 held)
//   ∂/∂w0  = G·(c0·G⁻¹·e_m + c1·B·G⁻¹·e_m)  (and i times it for the imaginary parts)
// So JᵀJ = Re Σ_mn S_mn·(V_m^H·V_n) with the 5×5 Gram sums S_mn = Σ_k conj(c_m)·c_n, and
// Jᵀe = Re Σ_m V_m^H·E_m with E_m = Σ_k conj(c_m)·e_k: the sample loop accumulates 15 + 10 complex
// products, independent of the number of parameters. The residuals e_k are formed sample by sample,
// so the gradient (which alone decides the converged point) is as accurate as a direct evaluation.
void OutputErrorProblem::LinearizeRun(std::size_t r, const FullParameters& p,
                                      const Eigen::Vector4d& w0, Eigen::MatrixXd* h,
                                      Eigen::VectorXd* g, double* cost) const {
  constexpr int kBasis = 5;
  using Coefficients = std::array<CVector2, kBasis>;
  const RunData& run = runs_[r];
  const int nf = NumFree();
  const FreeRunPropagator propagator(run.omega_rad_s, DeltaOf(p));
  const CMatrix2& b = propagator.B();
  const CMatrix2 gain = PickoffGain(XiOf(p));
  const CMatrix2 gain_inv = gain.inverse();
  const CVector2 u0 = gain_inv * ToComplex(w0);
  const CVector2 bu0 = b * u0;
  const CVector2 g_u0 = gain * u0;
  const CVector2 g_bu0 = gain * bu0;

  // Sample loop: Gram sums, projected residuals, cost. Fixed-size storage only.
  Eigen::Matrix<Complex, kBasis, kBasis> gram = Eigen::Matrix<Complex, kBasis, kBasis>::Zero();
  Coefficients projected;
  for (CVector2& e : projected) e.setZero();
  double sum = 0.0;
  {
    const NoAllocationScope no_allocation;
    propagator.ForEachSample(run.t_s, [&](std::size_t k, const PropagatorScalars& s) {
      const double t = run.t_s[k];
      Complex c[kBasis];
      c[0] = s.decay * s.f0;
      c[1] = s.decay * s.f1;
      c[2] = t * c[0];
      c[3] = t * c[1];
      c[4] = s.decay * s.df1_dmu2;
      const CVector2 e =
          ToComplex(run.y.col(static_cast<Eigen::Index>(k))) - (c[0] * g_u0 + c[1] * g_bu0);
      sum += std::norm(e[0]) + std::norm(e[1]);
      for (int m = 0; m < kBasis; ++m) {
        const Complex cm = std::conj(c[m]);
        projected[static_cast<std::size_t>(m)] += cm * e;
        for (int n = m; n < kBasis; ++n) gram(m, n) += cm * c[n];
      }
    });
  }
  for (int m = 0; m < kBasis; ++m)
    for (int n = 0; n < m; ++n) gram(m, n) = std::conj(gram(n, m));

  // Coefficient vectors of every column: the free parameters, then w0.
  const int cols = nf + 4;
  std::array<Coefficients, 14> v;
  for (Coefficients& column : v)
    for (CVector2& entry : column) entry.setZero();
  std::array<CVector2, 4> c_u0;   // Ck·u0
  std::array<CVector2, 4> c_bu0;  // Ck·B·u0
  XiDerivatives(u0, &c_u0);
  XiDerivatives(bu0, &c_bu0);
  for (int col = 0; col < nf; ++col) {
    const int which = free_[static_cast<std::size_t>(col)];
    Coefficients& vc = v[static_cast<std::size_t>(col)];
    if (which == kDamping) {
      vc[2] = g_u0;
      vc[3] = g_bu0;
    } else if (which < kXiOffset) {
      const Complex dmu2 = propagator.Mu2Derivative(which);
      vc[3] = (0.5 * dmu2) * g_u0;
      vc[4] = dmu2 * g_bu0;
      vc[1] = gain * (propagator.BCoefficient(which) * Pauli(propagator.BPauli(which), u0));
    } else {
      const auto k = static_cast<std::size_t>(which - kXiOffset);
      const CVector2 a = gain_inv * c_u0[k];
      vc[0] = c_u0[k] - gain * a;
      vc[1] = c_bu0[k] - gain * (b * a);
    }
  }
  const CMatrix2 g_b_ginv = gain * b * gain_inv;
  const Complex i(0, 1);
  for (int m = 0; m < 2; ++m) {
    Coefficients& re = v[static_cast<std::size_t>(nf + 2 * m)];
    Coefficients& im = v[static_cast<std::size_t>(nf + 2 * m + 1)];
    re[0] = CVector2::Unit(m);
    re[1] = g_b_ginv.col(m);
    im[0] = i * re[0];
    im[1] = i * re[1];
  }

  h->resize(cols, cols);
  g->resize(cols);
  for (int a = 0; a < cols; ++a) {
    const Coefficients& va = v[static_cast<std::size_t>(a)];
    Complex ga = 0.0;
    for (int m = 0; m < kBasis; ++m)
      ga += va[static_cast<std::size_t>(m)].dot(projected[static_cast<std::size_t>(m)]);
    (*g)[a] = ga.real();
    for (int bb = 0; bb <= a; ++bb) {
      const Coefficients& vb = v[static_cast<std::size_t>(bb)];
      Complex hab = 0.0;
      for (int m = 0; m < kBasis; ++m)
        for (int n = 0; n < kBasis; ++n)
          hab += gram(m, n) * va[static_cast<std::size_t>(m)].dot(vb[static_cast<std::size_t>(n)]);
      (*h)(a, bb) = hab.real();
      (*h)(bb, a) = hab.real();
    }
  }
  *cost = sum;
}

void OutputErrorProblem::Linearize(const FullParameters& p, const std::vector<Eigen::Vector4d>& w0,
                                   NormalEquations* ne) const {
  const int nf = NumFree();
  const std::size_t n_runs = runs_.size();
  std::vector<Eigen::MatrixXd> h(n_runs);
  std::vector<Eigen::VectorXd> g(n_runs);
  ne->cost_per_run.assign(n_runs, 0.0);
  ParallelFor(n_runs, threads_, [&](std::size_t r) {
    LinearizeRun(r, p, w0[r], &h[r], &g[r], &ne->cost_per_run[r]);
  });
  ne->h_pp = Eigen::MatrixXd::Zero(nf, nf);
  ne->g_p = Eigen::VectorXd::Zero(nf);
  ne->h_px.resize(n_runs);
  ne->h_xx.resize(n_runs);
  ne->g_x.resize(n_runs);
  ne->cost = 0.0;
  for (std::size_t r = 0; r < n_runs; ++r) {
    ne->h_pp += h[r].topLeftCorner(nf, nf);
    ne->g_p += g[r].head(nf);
    ne->h_px[r] = h[r].topRightCorner(nf, 4);
    ne->h_xx[r] = h[r].bottomRightCorner<4, 4>();
    ne->g_x[r] = g[r].tail<4>();
    ne->cost += ne->cost_per_run[r];
  }
}

bool OutputErrorProblem::SolveInitialStates(const FullParameters& p,
                                            std::vector<Eigen::Vector4d>* w0) const {
  const CMatrix2 gain = PickoffGain(XiOf(p));
  w0->resize(runs_.size());
  std::vector<char> ok(runs_.size(), 0);
  ParallelFor(runs_.size(), threads_, [&](std::size_t r) {
    const RunData& run = runs_[r];
    const FreeRunPropagator propagator(run.omega_rad_s, DeltaOf(p));
    // The model is complex-linear in u0, so the normal equations are complex 2×2.
    CMatrix2 normal = CMatrix2::Zero();
    CVector2 rhs = CVector2::Zero();
    const NoAllocationScope no_allocation;
    propagator.ForEachSample(run.t_s, [&](std::size_t k, const PropagatorScalars& s) {
      const CMatrix2 gphi = gain * propagator.Transition(s);
      normal.noalias() += gphi.adjoint() * gphi;
      rhs.noalias() += gphi.adjoint() * ToComplex(run.y.col(static_cast<Eigen::Index>(k)));
    });
    if (!(std::abs(normal.determinant()) > 0.0)) return;
    const CVector2 u0 = normal.inverse() * rhs;
    if (!u0.allFinite()) return;
    (*w0)[r] = ToReal(CVector2(gain * u0));
    ok[r] = 1;
  });
  return std::all_of(ok.begin(), ok.end(), [](char c) { return c != 0; });
}

namespace {

// Applies Marquardt damping to a copy of the blocks and eliminates x0.
bool Reduce(const NormalEquations& ne, double lambda, Eigen::MatrixXd* h_red,
            Eigen::VectorXd* g_red, std::vector<Eigen::Matrix4d>* h_xx_inv) {
  const Eigen::Index nf = ne.h_pp.rows();
  *h_red = ne.h_pp;
  h_red->diagonal() *= (1.0 + lambda);
  *g_red = ne.g_p;
  h_xx_inv->resize(ne.h_xx.size());
  for (std::size_t r = 0; r < ne.h_xx.size(); ++r) {
    Eigen::Matrix4d hxx = ne.h_xx[r];
    hxx.diagonal() *= (1.0 + lambda);
    Eigen::Matrix4d inv;
    if (!InvertScaledSpd(hxx, &inv)) return false;
    (*h_xx_inv)[r] = inv;
    if (nf > 0) {
      const Eigen::Matrix<double, Eigen::Dynamic, 4> b_inv = ne.h_px[r] * inv;
      h_red->noalias() -= b_inv * ne.h_px[r].transpose();
      g_red->noalias() -= b_inv * ne.g_x[r];
    }
  }
  return true;
}

}  // namespace

bool ReducedInformation(const NormalEquations& ne, Eigen::MatrixXd* h_reduced) {
  Eigen::VectorXd g;
  std::vector<Eigen::Matrix4d> inv;
  if (!Reduce(ne, 0.0, h_reduced, &g, &inv)) return false;
  *h_reduced = 0.5 * (*h_reduced + h_reduced->transpose());
  return true;
}

bool SolveDamped(const NormalEquations& ne, double lambda, Eigen::VectorXd* dp,
                 std::vector<Eigen::Vector4d>* dx0) {
  Eigen::MatrixXd h_red;
  Eigen::VectorXd g_red;
  std::vector<Eigen::Matrix4d> h_xx_inv;
  if (!Reduce(ne, lambda, &h_red, &g_red, &h_xx_inv)) return false;
  Eigen::VectorXd step = Eigen::VectorXd::Zero(ne.h_pp.rows());
  if (step.size() > 0 && !SolveScaledSpd(h_red, g_red, &step)) return false;
  *dp = step;
  dx0->resize(ne.h_xx.size());
  for (std::size_t r = 0; r < ne.h_xx.size(); ++r) {
    Eigen::Vector4d rhs = ne.g_x[r];
    if (step.size() > 0) rhs.noalias() -= ne.h_px[r].transpose() * step;
    (*dx0)[r] = h_xx_inv[r] * rhs;
  }
  return true;
}

}  // namespace hrgbench::estimator::internal

namespace hrgbench::estimator::internal {

Eigen::Vector4d TrueInitialState(const FullParameters& p, const Eigen::Vector4d& w0) {
  return ToReal(CVector2(PickoffGain(XiOf(p)).inverse() * ToComplex(w0)));
}

Eigen::Vector4d ObservedInitialState(const FullParameters& p, const Eigen::Vector4d& x0) {
  return ToReal(CVector2(PickoffGain(XiOf(p)) * ToComplex(x0)));
}

}  // namespace hrgbench::estimator::internal
