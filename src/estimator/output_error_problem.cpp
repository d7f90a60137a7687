#include "output_error_problem.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <type_traits>

#include "common_phase.hpp"
#include "free_run_propagator.hpp"
#include "least_squares_util.hpp"
#include "no_allocation_scope.hpp"
#include "parallel_for.hpp"

namespace hrgbench::estimator::internal {
namespace {

Delta DeltaOf(const FullParameters& p) { return p.head<6>(); }
Xi XiOf(const FullParameters& p) { return p.tail<4>(); }

// Number of basis functions of the sample loop for a common phase of degree D (see LinearizeRun).
constexpr int BasisCount(int degree) { return degree <= 1 ? 5 : 5 + 2 * (degree - 1); }
constexpr int kMaxBasis = BasisCount(kMaxPhaseDegree);
using Coefficients = std::array<CVector2, kMaxBasis>;

// Everything about one run's model that is constant over its samples.
struct RunModel {
  RunModel(double omega_rad_s, const FullParameters& p, const RunNuisance& n,
           const NuisanceModel& model, std::size_t r)
      : propagator(omega_rad_s + (model.OmegaFree(r) ? n[model.OmegaIndex()] : 0.0), DeltaOf(p)),
        gain(PickoffGain(XiOf(p))),
        gain_inv(gain.inverse()),
        u0(gain_inv * ToComplex(n.head<4>())),
        bu0(propagator.B() * u0),
        g_u0(gain * u0),
        g_bu0(gain * bu0),
        degree(model.phase_degree) {
    for (int j = 1; j <= degree; ++j)
      phase[static_cast<std::size_t>(j - 1)] = n[NuisanceModel::PhaseIndex(j)];
  }
  CommonPhase Phase() const { return CommonPhase(phase.data(), degree); }

  FreeRunPropagator propagator;
  CMatrix2 gain;
  CMatrix2 gain_inv;
  CVector2 u0;
  CVector2 bu0;
  CVector2 g_u0;
  CVector2 g_bu0;
  int degree;
  std::array<double, kMaxPhaseDegree> phase{};
};

// The basis functions at one time stamp, before the common phase: e^{αt}·(f0, f1, t·f0, t·f1,
// ∂f1/∂μ², t²·f0, t²·f1, t³·f0, t³·f1).
template <int kBasis>
inline void Basis(const PropagatorScalars& s, double t, Complex* c) {
  c[0] = s.decay * s.f0;
  c[1] = s.decay * s.f1;
  c[2] = t * c[0];
  c[3] = t * c[1];
  c[4] = s.decay * s.df1_dmu2;
  if constexpr (kBasis > 5) {
    c[5] = t * c[2];
    c[6] = t * c[3];
  }
  if constexpr (kBasis > 7) {
    c[7] = t * c[5];
    c[8] = t * c[6];
  }
}

// Visits every sample of a run with its basis values and its residual turned back by the common
// phase, e' = e^{−iψ(t)}·(y − ŷ): every pass over the data is this loop. Does not allocate.
template <int kBasis, typename Fn>
void ForEachResidual(const RunData& run, const RunModel& m, Fn fn) {
  CommonPhase phase = m.Phase();
  const NoAllocationScope no_allocation;
  m.propagator.ForEachSample(run.t_s, [&](std::size_t k, const PropagatorScalars& s) {
    const double t = run.t_s[k];
    Complex c[kBasis];
    Basis<kBasis>(s, t, c);
    const Complex rot = phase.Next(t);
    // Written per entry: as one Eigen expression GCC called it out of line for every sample (~10 %
    // of the estimate's time). Same operations in the same order, so the same rounding.
    const auto col = static_cast<Eigen::Index>(k);
    const Complex turn = std::conj(rot);
    CVector2 e_turned;
    e_turned[0] =
        turn * Complex(run.y(0, col), run.y(1, col)) - (c[0] * m.g_u0[0] + c[1] * m.g_bu0[0]);
    e_turned[1] =
        turn * Complex(run.y(2, col), run.y(3, col)) - (c[0] * m.g_u0[1] + c[1] * m.g_bu0[1]);
    fn(k, c, rot, e_turned);
  });
}

// Coefficient vectors of every Jacobian column of run r over the basis: the free parameters, then
// the run's nuisance (w0, q_1 … q_D, ΔΩ).
void ColumnCoefficients(const RunModel& m, const std::vector<int>& free, const NuisanceModel& model,
                        std::size_t r, const FullParameters& p, std::vector<Coefficients>* v) {
  const int nf = static_cast<int>(free.size());
  v->resize(static_cast<std::size_t>(nf + model.Size(r)));
  for (Coefficients& column : *v)
    for (CVector2& entry : column) entry.setZero();
  const FreeRunPropagator& propagator = m.propagator;
  const CMatrix2& b = propagator.B();
  std::array<CVector2, 4> c_u0;   // Ck·u0
  std::array<CVector2, 4> c_bu0;  // Ck·B·u0
  XiDerivatives(m.u0, &c_u0);
  XiDerivatives(m.bu0, &c_bu0);
  // A parameter entering through B: ∂B = coefficient·σ_pauli, ∂μ² = dmu2.
  const auto through_b = [&](Complex coefficient, int pauli, Complex dmu2, Coefficients* vc) {
    (*vc)[3] = (0.5 * dmu2) * m.g_u0;
    (*vc)[4] = dmu2 * m.g_bu0;
    (*vc)[1] = m.gain * (coefficient * Pauli(pauli, m.u0));
  };
  for (int col = 0; col < nf; ++col) {
    const int which = free[static_cast<std::size_t>(col)];
    Coefficients& vc = (*v)[static_cast<std::size_t>(col)];
    if (which == kDamping) {
      vc[2] = m.g_u0;
      vc[3] = m.g_bu0;
    } else if (which < kXiOffset) {
      through_b(propagator.BCoefficient(which), propagator.BPauli(which),
                propagator.Mu2Derivative(which), &vc);
    } else {
      const auto k = static_cast<std::size_t>(which - kXiOffset);
      const CVector2 a = m.gain_inv * c_u0[k];
      vc[0] = c_u0[k] - m.gain * a;
      vc[1] = c_bu0[k] - m.gain * (b * a);
    }
  }
  const CMatrix2 g_b_ginv = m.gain * b * m.gain_inv;
  const Complex i(0, 1);
  for (int w = 0; w < 2; ++w) {
    Coefficients& re = (*v)[static_cast<std::size_t>(nf + 2 * w)];
    Coefficients& im = (*v)[static_cast<std::size_t>(nf + 2 * w + 1)];
    re[0] = CVector2::Unit(w);
    re[1] = g_b_ginv.col(w);
    im[0] = i * re[0];
    im[1] = i * re[1];
  }
  // ∂ŷ/∂q_j = i·t^j·ŷ: t·f0, t·f1 are basis 2, 3; t^j·f0, t^j·f1 are 5 + 2(j − 2), 6 + 2(j − 2).
  for (int j = 1; j <= model.phase_degree; ++j) {
    Coefficients& vc = (*v)[static_cast<std::size_t>(nf + NuisanceModel::PhaseIndex(j))];
    const std::size_t f0_index = j == 1 ? 2 : static_cast<std::size_t>(5 + 2 * (j - 2));
    vc[f0_index] = i * m.g_u0;
    vc[f0_index + 1] = i * m.g_bu0;
  }
  // ΔΩ enters as βy = i·2Ωδ2: ∂B/∂Ω = i·2δ2·σy, ∂μ²/∂Ω = 2βy·i·2δ2.
  if (model.OmegaFree(r)) {
    const Complex coefficient = i * (2.0 * p[kScaleFactor]);
    through_b(coefficient, 1, 2.0 * propagator.BetaY() * coefficient,
              &(*v)[static_cast<std::size_t>(nf + model.OmegaIndex())]);
  }
}

template <typename Fn>
void DispatchBasis(int degree, Fn fn) {
  switch (BasisCount(degree)) {
    case 5:
      fn(std::integral_constant<int, 5>{});
      break;
    case 7:
      fn(std::integral_constant<int, 7>{});
      break;
    default:
      fn(std::integral_constant<int, 9>{});
      break;
  }
}

// JᵀJ (and Jᵀe when `projected` is given) of a run's columns from the Gram sums of its basis
// functions and the columns' coefficient vectors over them (LinearizeRunWithBasis says why).
template <int kBasis>
void NormalBlock(const std::vector<Coefficients>& v,
                 const Eigen::Matrix<Complex, kBasis, kBasis>& gram, const CVector2* projected,
                 Eigen::MatrixXd* h, Eigen::VectorXd* g) {
  const auto cols = static_cast<Eigen::Index>(v.size());
  h->resize(cols, cols);
  if (projected != nullptr) g->resize(cols);
  for (Eigen::Index a = 0; a < cols; ++a) {
    const Coefficients& va = v[static_cast<std::size_t>(a)];
    if (projected != nullptr) {
      Complex ga = 0.0;
      for (int i = 0; i < kBasis; ++i) ga += va[static_cast<std::size_t>(i)].dot(projected[i]);
      (*g)[a] = ga.real();
    }
    for (Eigen::Index bb = 0; bb <= a; ++bb) {
      const Coefficients& vb = v[static_cast<std::size_t>(bb)];
      Complex hab = 0.0;
      for (int i = 0; i < kBasis; ++i)
        for (int j = 0; j < kBasis; ++j)
          hab += gram(i, j) * va[static_cast<std::size_t>(i)].dot(vb[static_cast<std::size_t>(j)]);
      (*h)(a, bb) = hab.real();
      (*h)(bb, a) = hab.real();
    }
  }
}

}  // namespace

FullParameters Pack(const Delta& delta, const Xi& xi) {
  FullParameters p;
  p << delta, xi;
  return p;
}

OutputErrorProblem::OutputErrorProblem(const RunSet& runs, std::vector<int> free, int threads,
                                       std::size_t min_samples_for_threads, NuisanceModel nuisance)
    : runs_(runs), free_(std::move(free)), nuisance_(std::move(nuisance)) {
  samples_ = runs_.TotalSamples();
  threads_ = samples_ < min_samples_for_threads ? 1 : ResolveThreads(threads, runs_.size());
}

int OutputErrorProblem::NumNuisanceDegreesOfFreedom() const {
  // A free ΔΩ comes with its prior's pseudo-observation: it costs no degree of freedom.
  return static_cast<int>(runs_.size()) * (4 + nuisance_.phase_degree);
}

double OutputErrorProblem::Cost(const FullParameters& p, const std::vector<RunNuisance>& nuisance,
                                std::vector<double>* per_run) const {
  std::vector<double> sums(runs_.size(), 0.0);
  ParallelFor(runs_.size(), threads_, [&](std::size_t r) {
    const RunPtr run = runs_.Load(r);
    const RunModel m(run->omega_rad_s, p, nuisance[r], nuisance_, r);
    double sum = 0.0;
    DispatchBasis(nuisance_.phase_degree, [&](auto basis) {
      ForEachResidual<decltype(basis)::value>(
          *run, m, [&](std::size_t, const Complex*, Complex, const CVector2& e) {
            sum += std::norm(e[0]) + std::norm(e[1]);
          });
    });
    sums[r] = sum;
  });
  double total = 0.0;
  for (std::size_t r = 0; r < runs_.size(); ++r) {
    total += sums[r];
    if (nuisance_.OmegaFree(r)) {
      const double offset = nuisance[r][nuisance_.OmegaIndex()];
      total += nuisance_.omega_prior_weight[r] * offset * offset;
    }
  }
  if (per_run) *per_run = std::move(sums);
  return total;
}

// Every Jacobian column, and the model itself, is a combination of a few complex functions of time,
//   c = e^{αt}·(f0, f1, t·f0, t·f1, ∂f1/∂μ², t²·f0, t²·f1, …),
// turned by the common phase e^{iψ(t)}, with coefficient vectors that are constant over a run (see
// free_run_propagator.hpp and ColumnCoefficients):
//   ŷ      = G·(c0·u0 + c1·B·u0)
//   ∂/∂δ1  = G·(c2·u0 + c3·B·u0)                                  (t·ŷ)
//   ∂/∂δj  = G·(∂μ²/∂δj·(c3/2·u0 + c4·B·u0) + c1·βj·σj·u0)         (j ≥ 2; ΔΩ alike)
//   ∂/∂ξk  = Ck·(c0·u0 + c1·B·u0) − G·(c0·a_k + c1·B·a_k),  a_k = G⁻¹·Ck·u0   (w0 held)
//   ∂/∂w0  = G·(c0·G⁻¹·e_m + c1·B·G⁻¹·e_m)  (and i times it for the imaginary parts)
//   ∂/∂q_j = i·t^j·ŷ
// So JᵀJ = Re Σ_mn S_mn·(V_m^H·V_n) with the Gram sums S_mn = Σ_k conj(c_m)·c_n (the common phase
// has modulus 1 and cancels), and Jᵀe = Re Σ_m V_m^H·E_m with E_m = Σ_k conj(c_m)·e^{−iψ}·e_k: the
// sample loop's work depends on the number of basis functions, not of parameters. The residuals are
// formed sample by sample, so the gradient (which alone decides the converged point) is as accurate
// as a direct evaluation.
template <int kBasis>
void OutputErrorProblem::LinearizeRunWithBasis(std::size_t r, const FullParameters& p,
                                               const RunNuisance& nuisance, Eigen::MatrixXd* h,
                                               Eigen::VectorXd* g, Eigen::MatrixXcd* gram_out,
                                               double* cost) const {
  const RunPtr run = runs_.Load(r);
  const RunModel m(run->omega_rad_s, p, nuisance, nuisance_, r);
  // Every basis function is t^k times one of three: c_a = t^{k_a}·b_{u_a} with b = (c0, c1, c4)
  // (Basis). So the Gram sums are moments of three products, S_ab = Σ t^{k_a+k_b}·conj(b_u)·b_v,
  // and the projections moments of three, E_a = Σ t^{k_a}·conj(b_u)·e: per sample six products
  // and real scalings by t instead of kBasis²/2 + kBasis complex products.
  constexpr int kPower = (kBasis - 3) / 2;  // highest power of t on c0, c1: 1, 2, 3
  constexpr std::array<int, 9> kFamily = {0, 1, 0, 1, 2, 0, 1, 0, 1};
  constexpr std::array<int, 9> kTPower = {0, 0, 1, 1, 0, 2, 2, 3, 3};
  // The moments as plain doubles, so the sample loop's additions and scalings by t are packed
  // (two per instruction): per power j, `low` holds |c0|², |c1|², conj(c0)·c1 (j ≤ 2·kPower) and
  // `high` conj(c4)·c0, conj(c4)·c1, conj(c0)·e, conj(c1)·e (j ≤ kPower).
  constexpr int kLow = 4, kHigh = 12;
  std::array<std::array<double, kLow>, 2 * kPower + 1> low{};
  std::array<std::array<double, kHigh>, kPower + 1> high{};
  double m22 = 0.0;
  CVector2 q2 = CVector2::Zero();
  double sum = 0.0;
  // The moments need c0, c1 and c4 only: the basis of five.
  ForEachResidual<5>(*run, m, [&](std::size_t k, const Complex* c, Complex, const CVector2& e) {
    sum += std::norm(e[0]) + std::norm(e[1]);
    const double t = run->t_s[k];
    const Complex b0 = std::conj(c[0]), b1 = std::conj(c[1]);
    const Complex b2 = std::conj(c[4]);
    const Complex x01 = b0 * c[1];
    const Complex x20 = b2 * c[0], x21 = b2 * c[1];
    const Complex y00 = b0 * e[0], y01 = b0 * e[1], y10 = b1 * e[0], y11 = b1 * e[1];
    m22 += std::norm(c[4]);
    q2 += b2 * e;
    std::array<double, kLow> xl = {std::norm(c[0]), std::norm(c[1]), x01.real(), x01.imag()};
    std::array<double, kHigh> xh = {x20.real(), x20.imag(), x21.real(), x21.imag(),
                                    y00.real(), y00.imag(), y01.real(), y01.imag(),
                                    y10.real(), y10.imag(), y11.real(), y11.imag()};
#pragma GCC unroll 8
    for (int j = 0; j <= 2 * kPower; ++j) {
      auto& acc = low[static_cast<std::size_t>(j)];
      for (int i = 0; i < kLow; ++i) {
        acc[static_cast<std::size_t>(i)] += xl[static_cast<std::size_t>(i)];
        xl[static_cast<std::size_t>(i)] *= t;
      }
    }
#pragma GCC unroll 8
    for (int j = 0; j <= kPower; ++j) {
      auto& acc = high[static_cast<std::size_t>(j)];
      for (int i = 0; i < kHigh; ++i) {
        acc[static_cast<std::size_t>(i)] += xh[static_cast<std::size_t>(i)];
        xh[static_cast<std::size_t>(i)] *= t;
      }
    }
  });
  std::array<double, 2 * kPower + 1> m00{}, m11{};
  std::array<Complex, 2 * kPower + 1> m01{};
  for (std::size_t j = 0; j < low.size(); ++j) {
    m00[j] = low[j][0];
    m11[j] = low[j][1];
    m01[j] = Complex(low[j][2], low[j][3]);
  }
  std::array<Complex, kPower + 1> m20{}, m21{};
  std::array<CVector2, kPower + 1> q0, q1;
  for (std::size_t j = 0; j < high.size(); ++j) {
    const auto& x = high[j];
    m20[j] = Complex(x[0], x[1]);
    m21[j] = Complex(x[2], x[3]);
    q0[j] = CVector2(Complex(x[4], x[5]), Complex(x[6], x[7]));
    q1[j] = CVector2(Complex(x[8], x[9]), Complex(x[10], x[11]));
  }
  // S_ab from the moments: conj(b_u)·b_v for u ≤ v in the family order (0, 1, 2 = c4).
  const auto moment = [&](int u, int v, int power) -> Complex {
    const auto i = static_cast<std::size_t>(power);
    if (u == v) return u == 0 ? Complex(m00[i]) : u == 1 ? Complex(m11[i]) : Complex(m22);
    if (u == 0 && v == 1) return m01[i];
    if (u == 1 && v == 0) return std::conj(m01[i]);
    if (u == 2) return v == 0 ? m20[i] : m21[i];
    return std::conj(u == 0 ? m20[i] : m21[i]);  // v == 2
  };
  Eigen::Matrix<Complex, kBasis, kBasis> gram;
  std::array<CVector2, kBasis> projected;
  for (int a = 0; a < kBasis; ++a) {
    const auto sa = static_cast<std::size_t>(a);
    const auto ka = static_cast<std::size_t>(kTPower[sa]);
    projected[sa] = kFamily[sa] == 0 ? q0[ka] : kFamily[sa] == 1 ? q1[ka] : q2;
    for (int b = 0; b < kBasis; ++b) {
      const auto sb = static_cast<std::size_t>(b);
      gram(a, b) = moment(kFamily[sa], kFamily[sb], kTPower[sa] + kTPower[sb]);
    }
  }

  std::vector<Coefficients> v;
  ColumnCoefficients(m, free_, nuisance_, r, p, &v);
  NormalBlock<kBasis>(v, gram, projected.data(), h, g);
  *gram_out = gram;
  *cost = sum;
}

void OutputErrorProblem::LinearizeRun(std::size_t r, const FullParameters& p,
                                      const RunNuisance& nuisance, Eigen::MatrixXd* h,
                                      Eigen::VectorXd* g, Eigen::MatrixXcd* gram,
                                      double* cost) const {
  DispatchBasis(nuisance_.phase_degree, [&](auto basis) {
    LinearizeRunWithBasis<decltype(basis)::value>(r, p, nuisance, h, g, gram, cost);
  });
}

void OutputErrorProblem::Linearize(const FullParameters& p,
                                   const std::vector<RunNuisance>& nuisance,
                                   NormalEquations* ne) const {
  const std::size_t n_runs = runs_.size();
  std::vector<Eigen::MatrixXd> h(n_runs);
  std::vector<Eigen::VectorXd> g(n_runs);
  ne->cost_per_run.assign(n_runs, 0.0);
  ne->gram.resize(n_runs);
  ParallelFor(n_runs, threads_, [&](std::size_t r) {
    LinearizeRun(r, p, nuisance[r], &h[r], &g[r], &ne->gram[r], &ne->cost_per_run[r]);
  });
  ne->p = p;
  ne->nuisance = nuisance;
  Assemble(h, g, nuisance, ne);
}

void OutputErrorProblem::Assemble(const std::vector<Eigen::MatrixXd>& h,
                                  const std::vector<Eigen::VectorXd>& g,
                                  const std::vector<RunNuisance>& nuisance,
                                  NormalEquations* ne) const {
  const int nf = NumFree();
  const std::size_t n_runs = runs_.size();
  ne->h_pp = Eigen::MatrixXd::Zero(nf, nf);
  ne->g_p = Eigen::VectorXd::Zero(nf);
  ne->h_px.resize(n_runs);
  ne->h_xx.resize(n_runs);
  ne->g_x.resize(n_runs);
  ne->cost = 0.0;
  for (std::size_t r = 0; r < n_runs; ++r) {
    const int nx = nuisance_.Size(r);
    ne->h_pp += h[r].topLeftCorner(nf, nf);
    ne->g_p += g[r].head(nf);
    ne->h_px[r] = h[r].topRightCorner(nf, nx);
    ne->h_xx[r] = h[r].bottomRightCorner(nx, nx);
    ne->g_x[r] = g[r].tail(nx);
    ne->cost += ne->cost_per_run[r];
    if (nuisance_.OmegaFree(r)) {
      // The prior: a pseudo-observation "ΔΩ = 0" of weight w.
      const int o = nuisance_.OmegaIndex();
      const double w = nuisance_.omega_prior_weight[r];
      const double offset = nuisance[r][o];
      ne->h_xx[r](o, o) += w;
      ne->g_x[r][o] -= w * offset;
      ne->cost += w * offset * offset;
    }
  }
}

bool OutputErrorProblem::InformationAt(const NormalEquations& linearized,
                                       const std::vector<RunNuisance>& nuisance,
                                       NormalEquations* ne) const {
  const std::size_t n_runs = runs_.size();
  const int basis = BasisCount(nuisance_.phase_degree);
  if (linearized.gram.size() != n_runs || nuisance.size() != n_runs) return false;
  std::vector<Eigen::MatrixXd> h(n_runs);
  std::vector<Eigen::VectorXd> g(n_runs);
  for (std::size_t r = 0; r < n_runs; ++r) {
    if (linearized.gram[r].rows() != basis || linearized.gram[r].cols() != basis ||
        nuisance[r].size() != nuisance_.Size(r))
      return false;
    const RunModel m(runs_.Info(r).omega_rad_s, linearized.p, nuisance[r], nuisance_, r);
    std::vector<Coefficients> v;
    ColumnCoefficients(m, free_, nuisance_, r, linearized.p, &v);
    DispatchBasis(nuisance_.phase_degree, [&](auto b) {
      constexpr int kBasis = decltype(b)::value;
      const Eigen::Matrix<Complex, kBasis, kBasis> gram = linearized.gram[r];
      NormalBlock<kBasis>(v, gram, nullptr, &h[r], nullptr);
    });
    g[r] = Eigen::VectorXd::Zero(h[r].rows());
  }
  ne->cost_per_run = linearized.cost_per_run;
  ne->gram = linearized.gram;
  ne->p = linearized.p;
  ne->nuisance = nuisance;
  Assemble(h, g, nuisance, ne);
  return true;
}

bool OutputErrorProblem::SolveInitialStates(const FullParameters& p,
                                            std::vector<RunNuisance>* nuisance,
                                            InitialStatesCost* cost,
                                            Eigen::Index samples_per_run) const {
  nuisance->resize(runs_.size());
  std::vector<char> ok(runs_.size(), 0);
  std::vector<double> cost_per_run(runs_.size(), 0.0), norm2_per_run(runs_.size(), 0.0);
  ParallelFor(runs_.size(), threads_, [&](std::size_t r) {
    RunNuisance& n = (*nuisance)[r];
    if (n.size() != nuisance_.Size(r)) n = RunNuisance::Zero(nuisance_.Size(r));
    const RunPtr loaded = runs_.Load(r);
    const Eigen::Index stride =
        samples_per_run > 0 ? std::max<Eigen::Index>(1, loaded->size() / samples_per_run) : 1;
    RunData thinned;
    if (stride > 1) {
      thinned.omega_rad_s = loaded->omega_rad_s;
      const Eigen::Index count = (loaded->size() + stride - 1) / stride;
      thinned.t_s.resize(static_cast<std::size_t>(count));
      thinned.y.resize(4, count);
      for (Eigen::Index k = 0; k < count; ++k) {
        thinned.t_s[static_cast<std::size_t>(k)] =
            loaded->t_s[static_cast<std::size_t>(k * stride)];
        thinned.y.col(k) = loaded->y.col(k * stride);
      }
    }
    const RunData& run = stride > 1 ? thinned : *loaded;
    n.head<4>().setZero();
    const RunModel m(run.omega_rad_s, p, n, nuisance_, r);
    // The model is complex-linear in u0, so the normal equations are complex 2×2 (and the common
    // phase, of modulus 1, only turns the data). With G·Φ(t) = c0·G + c1·G·B they follow from three
    // Gram sums of (c0, c1) and two projections of the turned data (u0 = 0 here, so
    // ForEachResidual's residual is the turned data).
    double s00 = 0.0, s11 = 0.0, yy = 0.0;
    Complex s01 = 0.0;
    CVector2 p0 = CVector2::Zero(), p1 = CVector2::Zero();
    ForEachResidual<5>(run, m, [&](std::size_t, const Complex* c, Complex, const CVector2& y) {
      const Complex b0 = std::conj(c[0]), b1 = std::conj(c[1]);
      yy += std::norm(y[0]) + std::norm(y[1]);
      s00 += std::norm(c[0]);
      s11 += std::norm(c[1]);
      s01 += b0 * c[1];
      p0 += b0 * y;
      p1 += b1 * y;
    });
    const CMatrix2 gb = m.gain * m.propagator.B();
    const CMatrix2 cross = s01 * (m.gain.adjoint() * gb);
    const CMatrix2 normal =
        s00 * (m.gain.adjoint() * m.gain) + cross + cross.adjoint() + s11 * (gb.adjoint() * gb);
    const CVector2 rhs = m.gain.adjoint() * p0 + gb.adjoint() * p1;
    if (!(std::abs(normal.determinant()) > 0.0)) return;
    const CVector2 u0 = normal.inverse() * rhs;
    if (!u0.allFinite()) return;
    n.head<4>() = ToReal(CVector2(m.gain * u0));
    cost_per_run[r] = yy - rhs.dot(u0).real();
    norm2_per_run[r] = yy;
    ok[r] = 1;
  });
  if (cost != nullptr) {
    *cost = InitialStatesCost{};
    for (std::size_t r = 0; r < runs_.size(); ++r) {
      cost->cost += cost_per_run[r];
      cost->data_norm2 += norm2_per_run[r];
      if (nuisance_.OmegaFree(r)) {
        const double offset = (*nuisance)[r][nuisance_.OmegaIndex()];
        cost->cost += nuisance_.omega_prior_weight[r] * offset * offset;
      }
    }
  }
  return std::all_of(ok.begin(), ok.end(), [](char c) { return c != 0; });
}

void OutputErrorProblem::RunResiduals(std::size_t r, const FullParameters& p,
                                      const RunNuisance& nuisance,
                                      Eigen::Matrix4Xd* residuals) const {
  const RunPtr loaded = runs_.Load(r);
  const RunData& run = *loaded;
  residuals->resize(4, run.size());
  const RunModel m(run.omega_rad_s, p, nuisance, nuisance_, r);
  // y − e^{iψ}·G·(c0·u0 + c1·B·u0) directly: not through ForEachResidual, whose residual is turned
  // back by the common phase (and would be turned forward again here), and whose other basis
  // functions this pass does not need.
  CommonPhase phase = m.Phase();
  const double* y = run.y.data();
  double* e = residuals->data();
  const NoAllocationScope no_allocation;
  m.propagator.ForEachSample(run.t_s, [&](std::size_t k, const PropagatorScalars& s) {
    const Complex c0 = s.decay * s.f0, c1 = s.decay * s.f1;
    const Complex rot = phase.Next(run.t_s[k]);
    const Complex model0 = rot * (c0 * m.g_u0[0] + c1 * m.g_bu0[0]);
    const Complex model1 = rot * (c0 * m.g_u0[1] + c1 * m.g_bu0[1]);
    const std::size_t i = 4 * k;
    e[i] = y[i] - model0.real();
    e[i + 1] = y[i + 1] - model0.imag();
    e[i + 2] = y[i + 2] - model1.real();
    e[i + 3] = y[i + 3] - model1.imag();
  });
}

void OutputErrorProblem::RunBlockScores(std::size_t r, const FullParameters& p,
                                        const RunNuisance& nuisance, std::size_t block_length,
                                        Eigen::MatrixXd* block_scores) const {
  const RunPtr loaded = runs_.Load(r);
  const RunData& run = *loaded;
  const RunModel m(run.omega_rad_s, p, nuisance, nuisance_, r);
  std::vector<Coefficients> v;
  ColumnCoefficients(m, free_, nuisance_, r, p, &v);
  const auto cols = static_cast<Eigen::Index>(v.size());
  const std::size_t n = static_cast<std::size_t>(run.size());
  const std::size_t length = std::max<std::size_t>(1, block_length);
  const auto blocks = static_cast<Eigen::Index>(std::max<std::size_t>(1, n / length));
  block_scores->setZero(cols, blocks);
  DispatchBasis(nuisance_.phase_degree, [&](auto basis) {
    constexpr int kBasis = decltype(basis)::value;
    std::array<CVector2, kBasis> projected;
    for (CVector2& e : projected) e.setZero();
    Eigen::Index block = 0;
    std::size_t in_block = 0;
    const auto flush = [&]() {
      for (Eigen::Index a = 0; a < cols; ++a) {
        Complex ga = 0.0;
        for (int i = 0; i < kBasis; ++i)
          ga += v[static_cast<std::size_t>(a)][static_cast<std::size_t>(i)].dot(
              projected[static_cast<std::size_t>(i)]);
        (*block_scores)(a, block) += ga.real();
      }
      for (CVector2& e : projected) e.setZero();
    };
    ForEachResidual<kBasis>(run, m, [&](std::size_t, const Complex* c, Complex, const CVector2& e) {
      for (int a = 0; a < kBasis; ++a)
        projected[static_cast<std::size_t>(a)] += std::conj(c[a]) * e;
      if (++in_block == length) {
        flush();
        in_block = 0;
        if (block + 1 < blocks) ++block;
      }
    });
    if (in_block > 0) flush();
  });
}

namespace {

// Applies Marquardt damping to a copy of the blocks and eliminates x0.
bool Reduce(const NormalEquations& ne, double lambda, Eigen::MatrixXd* h_red,
            Eigen::VectorXd* g_red, std::vector<Eigen::MatrixXd>* h_xx_inv) {
  const Eigen::Index nf = ne.h_pp.rows();
  *h_red = ne.h_pp;
  h_red->diagonal() *= (1.0 + lambda);
  *g_red = ne.g_p;
  h_xx_inv->resize(ne.h_xx.size());
  for (std::size_t r = 0; r < ne.h_xx.size(); ++r) {
    Eigen::MatrixXd hxx = ne.h_xx[r];
    hxx.diagonal() *= (1.0 + lambda);
    Eigen::MatrixXd inv;
    if (!InvertScaledSpd(hxx, &inv)) return false;
    (*h_xx_inv)[r] = inv;
    if (nf > 0) {
      const Eigen::MatrixXd b_inv = ne.h_px[r] * inv;
      h_red->noalias() -= b_inv * ne.h_px[r].transpose();
      g_red->noalias() -= b_inv * ne.g_x[r];
    }
  }
  return true;
}

}  // namespace

bool ReducedInformation(const NormalEquations& ne, Eigen::MatrixXd* h_reduced) {
  Eigen::VectorXd g;
  std::vector<Eigen::MatrixXd> inv;
  if (!Reduce(ne, 0.0, h_reduced, &g, &inv)) return false;
  *h_reduced = 0.5 * (*h_reduced + h_reduced->transpose());
  return true;
}

bool NuisanceProjections(const NormalEquations& ne, std::vector<Eigen::MatrixXd>* k) {
  k->resize(ne.h_xx.size());
  for (std::size_t r = 0; r < ne.h_xx.size(); ++r) {
    Eigen::MatrixXd inv;
    if (!InvertScaledSpd(ne.h_xx[r], &inv)) return false;
    (*k)[r] = ne.h_px[r] * inv;
  }
  return true;
}

bool SolveDamped(const NormalEquations& ne, double lambda, Eigen::VectorXd* dp,
                 std::vector<RunNuisance>* dx0) {
  Eigen::MatrixXd h_red;
  Eigen::VectorXd g_red;
  std::vector<Eigen::MatrixXd> h_xx_inv;
  if (!Reduce(ne, lambda, &h_red, &g_red, &h_xx_inv)) return false;
  Eigen::VectorXd step = Eigen::VectorXd::Zero(ne.h_pp.rows());
  if (step.size() > 0 && !SolveScaledSpd(h_red, g_red, &step)) return false;
  *dp = step;
  dx0->resize(ne.h_xx.size());
  for (std::size_t r = 0; r < ne.h_xx.size(); ++r) {
    Eigen::VectorXd rhs = ne.g_x[r];
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
