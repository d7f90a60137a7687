#pragma once
// Closed-form free-run propagation and its parameter derivatives, in the complex form of the model.
//
// With u = (x1 + i·x2, x3 + i·x4) the system matrix acts complex-linearly (model.md):
//   A = α·I + B,  α = δ1,  B = βx·σx + βy·σy + βz·σz,
//   βx = δ4 + i·δ6,  βy = i·2Ωδ2,  βz = δ3 + i·δ5.
// B is traceless, so B² = μ²·I with μ² = βx² + βy² + βz², and
//   exp(A·t) = e^{αt}·(f0(t)·I + f1(t)·B),  f0 = cosh(μt),  f1 = sinh(μt)/μ.
// f0 and f1 are entire functions of μ² (no branch of the square root matters); their derivatives
// in μ² give ∂exp(A·t)/∂δ in closed form: ∂f0/∂μ² = t·f1/2, ∂f1/∂μ² = (t·f0 − f1)/(2μ²) (series
// near μ = 0). Every time stamp is evaluated directly, so irregular sampling costs nothing and
// nothing accumulates over long runs.
// The distortion is complex-linear as well: I + C = [[1 + p, q], [q, 1 − p]], p = ξ1 − iξ2, q = ξ4
// − iξ3.
//
// Internal to the estimator library.

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <complex>
#include <vector>

#include "hrgbench/estimator/parameters.hpp"

namespace hrgbench::estimator::internal {

using Complex = std::complex<double>;
using CVector2 = Eigen::Matrix<Complex, 2, 1>;
using CMatrix2 = Eigen::Matrix<Complex, 2, 2>;

// Scalar functions of one time stamp.
struct PropagatorScalars {
  double decay = 1.0;      // e^{αt}
  Complex f0 = 1.0;        // cosh(μt)
  Complex f1 = 0.0;        // sinh(μt)/μ
  Complex df1_dmu2 = 0.0;  // ∂f1/∂μ²
};

class FreeRunPropagator {
 public:
  FreeRunPropagator(double omega_rad_s, const Delta& delta) noexcept;

  PropagatorScalars Scalars(double t_s) const noexcept;

  // exp(A·t) as a complex 2×2 matrix.
  CMatrix2 Transition(const PropagatorScalars& s) const noexcept;

  // exp(A·t)·u0.
  CVector2 Propagate(const PropagatorScalars& s, const CVector2& u0) const noexcept;

  // ∂(exp(A·t)·u0)/∂δj for j = 0..5, given v = exp(A·t)·u0.
  void DeltaDerivatives(const PropagatorScalars& s, double t_s, const CVector2& u0,
                        const CVector2& v, std::array<CVector2, 6>* dv) const noexcept;

  // The same scalars for the time stamps of a run, visited in order: fn(k, scalars).
  //
  // Most runs are uniformly sampled, and there e^{(α±μ)·t} advances by a constant factor per
  // sample: one complex product instead of two exponentials and a sincos. The recurrence restarts
  // from the closed form every kResyncSamples samples and whenever the step changes (a dropped
  // frame), so its rounding error stays below kResyncSamples ulp (~1e-14 relative); near μ·t = 0,
  // where the closed form cancels, the series is used as in Scalars().
  template <typename Fn>
  void ForEachSample(const std::vector<double>& t_s, Fn fn) const noexcept;

  const CMatrix2& B() const noexcept { return b_; }
  Complex Mu2() const noexcept { return mu2_; }
  Complex BetaY() const noexcept { return beta_y_; }  // i·2Ωδ2
  // ∂B/∂δj = BCoefficient(j)·σ_{BPauli(j)} (0 = σx, 1 = σy, 2 = σz), ∂μ²/∂δj = Mu2Derivative(j), j
  // ≥ 1.
  Complex BCoefficient(int j) const noexcept { return coefficient_[static_cast<std::size_t>(j)]; }
  int BPauli(int j) const noexcept { return pauli_[static_cast<std::size_t>(j)]; }
  Complex Mu2Derivative(int j) const noexcept { return dmu2_[static_cast<std::size_t>(j)]; }

 private:
  double alpha_ = 0.0;
  Complex beta_x_, beta_y_, beta_z_;
  Complex mu2_;
  Complex mu_;
  CMatrix2 b_;
  // ∂B/∂δj = coefficient_[j]·σ_{pauli_[j]}, ∂μ²/∂δj = dmu2_[j] (j ≥ 1).
  std::array<Complex, 6> coefficient_{};
  std::array<int, 6> pauli_{};  // 0 = σx, 1 = σy, 2 = σz
  std::array<Complex, 6> dmu2_{};
  double omega_rad_s_ = 0.0;
  Complex mu_inv_;        // 1/μ (0 when μ = 0)
  Complex half_mu2_inv_;  // 1/(2μ²)
};

inline constexpr int kResyncSamples = 64;

template <typename Fn>
void FreeRunPropagator::ForEachSample(const std::vector<double>& t_s, Fn fn) const noexcept {
  // Closed form of decay·e^{±μt} from one sincos and two real exponentials.
  const auto exact = [this](double t, Complex* plus, Complex* minus) {
    const double phase = mu_.imag() * t;
    const double c = std::cos(phase), s = std::sin(phase);
    const double grow = std::exp((alpha_ + mu_.real()) * t);
    const double shrink = std::exp((alpha_ - mu_.real()) * t);
    *plus = Complex(grow * c, grow * s);
    *minus = Complex(shrink * c, -shrink * s);
  };
  // Same threshold as Scalars(): below it the series; above it the recurrence loses at most
  // eps/|μt|² ≈ 1e-14 relative to cancellation in ∂f1/∂μ².
  const double series_t2 = std::norm(mu2_) > 0.0 ? 1e-2 / std::sqrt(std::norm(mu2_)) : 0.0;
  Complex plus, minus, step_plus, step_minus;
  double step = 0.0;
  int since_sync = kResyncSamples;
  for (std::size_t k = 0; k < t_s.size(); ++k) {
    const double t = t_s[k];
    if (t * t < series_t2 || mu2_ == Complex(0.0)) {
      fn(k, Scalars(t));
      since_sync = kResyncSamples;
      continue;
    }
    const double dt = k > 0 ? t - t_s[k - 1] : 0.0;
    if (since_sync >= kResyncSamples || !(std::abs(dt - step) <= 1e-9 * step)) {
      exact(t, &plus, &minus);
      if (!(std::abs(dt - step) <= 1e-9 * step) && dt > 0.0) {
        step = dt;
        exact(step, &step_plus, &step_minus);
      }
      since_sync = 0;
    } else {
      plus *= step_plus;
      minus *= step_minus;
      ++since_sync;
    }
    PropagatorScalars s;
    s.decay = 1.0;  // folded into f0, f1, ∂f1/∂μ² below
    s.f0 = 0.5 * (plus + minus);
    s.f1 = 0.5 * (plus - minus) * mu_inv_;
    s.df1_dmu2 = (t * s.f0 - s.f1) * half_mu2_inv_;
    fn(k, s);
  }
}

// σx·u, σy·u, σz·u.
inline CVector2 PauliX(const CVector2& u) { return CVector2(u[1], u[0]); }
inline CVector2 PauliY(const CVector2& u) {
  return CVector2(Complex(0, -1) * u[1], Complex(0, 1) * u[0]);
}
inline CVector2 PauliZ(const CVector2& u) { return CVector2(u[0], -u[1]); }
inline CVector2 Pauli(int which, const CVector2& u) {
  return which == 0 ? PauliX(u) : (which == 1 ? PauliY(u) : PauliZ(u));
}

// The pick-off path I + C(ξ) as a complex 2×2 matrix.
CMatrix2 PickoffGain(const Xi& xi) noexcept;

// ∂((I + C(ξ))·v)/∂ξk for k = 0..3.
inline void XiDerivatives(const CVector2& v, std::array<CVector2, 4>* dy) noexcept {
  const Complex minus_i(0, -1);
  (*dy)[0] = PauliZ(v);
  (*dy)[1] = minus_i * PauliZ(v);
  (*dy)[2] = minus_i * PauliX(v);
  (*dy)[3] = PauliX(v);
}

inline CVector2 ToComplex(const Eigen::Vector4d& x) {
  return CVector2(Complex(x[0], x[1]), Complex(x[2], x[3]));
}
inline Eigen::Vector4d ToReal(const CVector2& u) {
  return Eigen::Vector4d(u[0].real(), u[0].imag(), u[1].real(), u[1].imag());
}

}  // namespace hrgbench::estimator::internal
