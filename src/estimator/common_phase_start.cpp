#include "common_phase_start.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <vector>

#include "common_phase.hpp"
#include "free_run_propagator.hpp"
#include "parallel_for.hpp"

namespace hrgbench::estimator::internal {
namespace {

// The prefix that gives w0: long enough to average the noise of a few samples (and a filter's
// settling), short enough that ψ is still small there: 50 ms turns a 1 rad/s offset by 0.05 rad,
// which only turns w0 by a common phase (absorbed) and does not change the predicted orbit.
constexpr double kPrefixS = 0.05;
constexpr int kPrefixMinSamples = 8;
// Lag products summed per block: enough to average the noise of one product, few enough that 2ψ̇
// is constant over a block.
constexpr int kMaxBlockPairs = 16;
// Points of the refinement more than this far (rad of 2ψ) from the frequency fit are read as noise
// of a near-circular orbit, not as phase.
constexpr double kRefineGateRad = 1.0;

// Weighted least squares of Σ_j c_j·b_j(x) on (x, value, weight), the basis powers x^{first + j},
// j = 0 … count − 1, x in [0, 1]. False when singular.
bool FitPowers(const std::vector<double>& x, const std::vector<double>& value,
               const std::vector<double>& weight, int first, int count, Eigen::VectorXd* c) {
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(count, count);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(count);
  Eigen::VectorXd basis(count);
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (!(weight[k] > 0.0)) continue;
    double power = std::pow(x[k], first);
    for (int j = 0; j < count; ++j) {
      basis[j] = power;
      power *= x[k];
    }
    h.noalias() += weight[k] * basis * basis.transpose();
    g.noalias() += weight[k] * value[k] * basis;
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(h);
  if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-12)) return false;
  *c = ldlt.solve(g);
  return c->allFinite();
}

}  // namespace

bool StartCommonPhase(const RunData& run, double omega_offset_rad_s, const FullParameters& p,
                      int degree, double* q) {
  for (int j = 0; j < degree; ++j) q[j] = 0.0;
  const auto n = static_cast<std::size_t>(run.size());
  if (degree < 1 || n < 4) return degree < 1;
  const FreeRunPropagator propagator(run.omega_rad_s + omega_offset_rad_s, p.head<6>());
  const CMatrix2 gain = PickoffGain(p.tail<4>());
  const CMatrix2 gain_inv = gain.inverse();
  const auto transition = [&](double t) {
    return CMatrix2(gain * propagator.Transition(propagator.Scalars(t)) * gain_inv);
  };
  const auto observed = [&](std::size_t k) {
    const auto col = static_cast<Eigen::Index>(k);
    return CVector2(Complex(run.y(0, col), run.y(1, col)), Complex(run.y(2, col), run.y(3, col)));
  };

  // 1. w0 from the prefix.
  CMatrix2 normal = CMatrix2::Zero();
  CVector2 rhs = CVector2::Zero();
  for (std::size_t k = 0; k < n; ++k) {
    if (k >= static_cast<std::size_t>(kPrefixMinSamples) && run.t_s[k] - run.t_s[0] > kPrefixS)
      break;
    const CMatrix2 m = transition(run.t_s[k]);
    normal += m.adjoint() * m;
    rhs += m.adjoint() * observed(k);
  }
  if (!(std::abs(normal.determinant()) > 0.0)) return false;
  const CVector2 w0 = normal.inverse() * rhs;
  if (!w0.allFinite()) return false;

  // 2–3. h = (u1² + u2²)·conj(v1² + v2²) on the decimated grid.
  const std::size_t stride =
      std::max<std::size_t>(1, (n + kPhaseStartPoints - 1) / kPhaseStartPoints);
  std::vector<double> t;
  std::vector<Complex> h;
  for (std::size_t k = 0; k < n; k += stride) {
    const CVector2 u = observed(k);
    const CVector2 v = transition(run.t_s[k]) * w0;
    t.push_back(run.t_s[k]);
    h.push_back((u[0] * u[0] + u[1] * u[1]) * std::conj(v[0] * v[0] + v[1] * v[1]));
  }
  const std::size_t points = t.size();
  const double t_end = t.back();
  if (points < 3 || !(t_end > 0.0)) return false;
  const double nominal_step = (t.back() - t.front()) / static_cast<double>(points - 1);

  // 4a. 2ψ̇ per block from the lag products, fitted in x = t/t_end: 2ψ = Σ c_j·x^j with
  // c_j = 2q_j·t_end^j, so 2ψ̇ = Σ_j a_j·x^{j−1} with a_j = j·c_j/t_end.
  const int block_pairs = std::clamp(static_cast<int>(points / 256), 1, kMaxBlockPairs);
  std::vector<double> x, value, weight;
  Complex sum = 0.0;
  double sum_abs = 0.0, sum_abs_dt = 0.0, sum_abs_t = 0.0;
  int in_block = 0;
  for (std::size_t k = 1; k < points; ++k) {
    const double dt = t[k] - t[k - 1];
    if (dt > 0.0 && dt <= 2.0 * nominal_step) {
      const Complex z = h[k] * std::conj(h[k - 1]);
      const double a = std::abs(z);
      sum += z;
      sum_abs += a;
      sum_abs_dt += a * dt;
      sum_abs_t += a * 0.5 * (t[k] + t[k - 1]);
      ++in_block;
    }
    if (in_block == block_pairs || (k + 1 == points && in_block > 0)) {
      if (sum_abs > 0.0) {
        const double dt_mean = sum_abs_dt / sum_abs;
        x.push_back(sum_abs_t / sum_abs / t_end);
        value.push_back(std::arg(sum) / dt_mean);
        // arg(Σz) scatters as (noise of Σz)/|Σz|: the blocks where the orbit is near circular or
        // the data and the prediction disagree weigh little.
        weight.push_back(std::norm(sum) * dt_mean * dt_mean);
      }
      sum = 0.0;
      sum_abs = sum_abs_dt = sum_abs_t = 0.0;
      in_block = 0;
    }
  }
  Eigen::VectorXd a;
  if (static_cast<int>(x.size()) < degree || !FitPowers(x, value, weight, 0, degree, &a))
    return false;
  std::vector<double> c(static_cast<std::size_t>(degree));
  for (int j = 1; j <= degree; ++j) c[static_cast<std::size_t>(j - 1)] = a[j - 1] * t_end / j;

  // 4b. 2ψ itself: the phase left after turning back by the fit is small; fit it with a constant.
  std::vector<double> xs(points), residual(points), w(points);
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t k = 0; k < points; ++k) {
      xs[k] = t[k] / t_end;
      double two_psi = 0.0, power = xs[k];
      for (int j = 0; j < degree; ++j) {
        two_psi += c[static_cast<std::size_t>(j)] * power;
        power *= xs[k];
      }
      residual[k] = std::arg(h[k] * std::polar(1.0, -two_psi));
      w[k] = std::abs(residual[k]) <= kRefineGateRad ? std::norm(h[k]) : 0.0;
    }
    Eigen::VectorXd d;
    if (!FitPowers(xs, residual, w, 0, degree + 1, &d)) break;
    for (int j = 1; j <= degree; ++j) c[static_cast<std::size_t>(j - 1)] += d[j];
  }
  double scale = 1.0;
  for (int j = 1; j <= degree; ++j) {
    scale *= t_end;
    q[j - 1] = 0.5 * c[static_cast<std::size_t>(j - 1)] / scale;
  }
  for (int j = 0; j < degree; ++j) {
    if (!std::isfinite(q[j])) {
      for (int i = 0; i < degree; ++i) q[i] = 0.0;
      return false;
    }
  }
  return true;
}

std::vector<RunNuisance> StartNuisance(const RunSet& runs, const FullParameters& p,
                                       const NuisanceModel& model, int threads) {
  std::vector<RunNuisance> nuisance(runs.size());
  ParallelFor(runs.size(), threads, [&](std::size_t r) {
    nuisance[r] = RunNuisance::Zero(model.Size(r));
    if (model.phase_degree < 1) return;
    double q[kMaxPhaseDegree] = {};
    StartCommonPhase(*runs.Load(r), 0.0, p, model.phase_degree, q);
    for (int j = 1; j <= model.phase_degree; ++j)
      nuisance[r][NuisanceModel::PhaseIndex(j)] = q[j - 1];
  });
  return nuisance;
}

}  // namespace hrgbench::estimator::internal
