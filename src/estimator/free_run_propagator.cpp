#include "free_run_propagator.hpp"

#include <cmath>

namespace hrgbench::estimator::internal {
namespace {

// Below this |μ²t²| the series of f1 and ∂f1/∂μ² is used: 7 terms leave a truncation error under
// 1e-20 relative, while the closed form would lose digits to cancellation.
constexpr double kSeriesThreshold = 1e-2;

}  // namespace

FreeRunPropagator::FreeRunPropagator(double omega_rad_s, const Delta& d) noexcept
    : omega_rad_s_(omega_rad_s) {
  const Complex i(0, 1);
  alpha_ = d[kDamping];
  beta_x_ = Complex(d[kDampingAnisotropySin], d[kFrequencyAnisotropySin]);
  beta_y_ = i * (2.0 * omega_rad_s * d[kScaleFactor]);
  beta_z_ = Complex(d[kDampingAnisotropyCos], d[kFrequencyAnisotropyCos]);
  mu2_ = beta_x_ * beta_x_ + beta_y_ * beta_y_ + beta_z_ * beta_z_;
  mu_ = std::sqrt(mu2_);
  if (mu2_ != Complex(0.0)) {
    mu_inv_ = 1.0 / mu_;
    half_mu2_inv_ = 0.5 / mu2_;
  }
  b_ << beta_z_, beta_x_ - i * beta_y_, beta_x_ + i * beta_y_, -beta_z_;

  coefficient_[kScaleFactor] = i * (2.0 * omega_rad_s);
  pauli_[kScaleFactor] = 1;
  coefficient_[kDampingAnisotropyCos] = 1.0;
  pauli_[kDampingAnisotropyCos] = 2;
  coefficient_[kDampingAnisotropySin] = 1.0;
  pauli_[kDampingAnisotropySin] = 0;
  coefficient_[kFrequencyAnisotropyCos] = i;
  pauli_[kFrequencyAnisotropyCos] = 2;
  coefficient_[kFrequencyAnisotropySin] = i;
  pauli_[kFrequencyAnisotropySin] = 0;
  const std::array<Complex, 3> beta = {beta_x_, beta_y_, beta_z_};
  for (int j = 1; j < 6; ++j) dmu2_[j] = 2.0 * beta[pauli_[j]] * coefficient_[j];
}

PropagatorScalars FreeRunPropagator::Scalars(double t) const noexcept {
  PropagatorScalars s;
  s.decay = std::exp(alpha_ * t);
  const Complex m = mu2_ * (t * t);                          // μ²t²
  if (std::norm(m) < kSeriesThreshold * kSeriesThreshold) {  // |m| without hypot
    // f0 = Σ m^n/(2n)!, f1 = t·Σ m^n/(2n+1)!, ∂f1/∂μ² = t³·Σ (n+1)·m^n/(2n+3)!.
    Complex f0 = 0.0, g1 = 0.0, g2 = 0.0, mn = 1.0;
    double fact_even = 1.0;  // (2n)!
    for (int n = 0; n < 7; ++n) {
      const double fact_odd = fact_even * (2 * n + 1);                // (2n+1)!
      const double fact_odd3 = fact_odd * (2 * n + 2) * (2 * n + 3);  // (2n+3)!
      f0 += mn / fact_even;
      g1 += mn / fact_odd;
      g2 += mn * (static_cast<double>(n + 1) / fact_odd3);
      mn *= m;
      fact_even = fact_odd * (2 * n + 2);
    }
    s.f0 = f0;
    s.f1 = t * g1;
    s.df1_dmu2 = (t * t * t) * g2;
  } else {
    const Complex mt = mu_ * t;
    const Complex e = std::exp(mt);
    const Complex e_inv = 1.0 / e;
    s.f0 = 0.5 * (e + e_inv);
    s.f1 = 0.5 * (e - e_inv) / mu_;
    s.df1_dmu2 = (t * s.f0 - s.f1) / (2.0 * mu2_);
  }
  return s;
}

CMatrix2 FreeRunPropagator::Transition(const PropagatorScalars& s) const noexcept {
  CMatrix2 phi = s.f1 * b_;
  phi(0, 0) += s.f0;
  phi(1, 1) += s.f0;
  return s.decay * phi;
}

CVector2 FreeRunPropagator::Propagate(const PropagatorScalars& s,
                                      const CVector2& u0) const noexcept {
  return s.decay * (s.f0 * u0 + s.f1 * (b_ * u0));
}

void FreeRunPropagator::DeltaDerivatives(const PropagatorScalars& s, double t, const CVector2& u0,
                                         const CVector2& v,
                                         std::array<CVector2, 6>* dv) const noexcept {
  (*dv)[kDamping] = t * v;
  const CVector2 bu = b_ * u0;
  // Common part of every δj (j ≥ 1): ∂Φ/∂μ² · u0 = e^{αt}·(t·f1/2·u0 + ∂f1/∂μ²·B·u0).
  const CVector2 dphi_dmu2_u0 = s.decay * ((0.5 * t * s.f1) * u0 + s.df1_dmu2 * bu);
  const Complex decay_f1 = s.decay * s.f1;
  for (int j = 1; j < 6; ++j) {
    (*dv)[j] = dmu2_[j] * dphi_dmu2_u0 + (decay_f1 * coefficient_[j]) * Pauli(pauli_[j], u0);
  }
}

CMatrix2 PickoffGain(const Xi& xi) noexcept {
  const Complex p(xi[0], -xi[1]);
  const Complex q(xi[3], -xi[2]);
  CMatrix2 g;
  g << 1.0 + p, q, q, 1.0 - p;
  return g;
}

}  // namespace hrgbench::estimator::internal
