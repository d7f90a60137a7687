#pragma once
// The common phase of a run's slow variables: y(t) = e^{iψ(t)}·G·exp(A·t)·G⁻¹·w0 on both complex
// channels, with ψ(t) = Σ_{j=1..D} q_j·t^j a polynomial of degree D ≤ kMaxPhaseDegree (q_j in
// rad/s^j).
//
// Why: the demodulation reference of real electronics is not the resonator's phase. A reference
// frequency offset, a phase-locked loop that drifts, or a resonator whose frequency moves with
// temperature all multiply both complex channels u = (x1 + i·x2, x3 + i·x4) by one common factor
// e^{iψ(t)}. The paper's forms z = W(x)·x do not see it (they do not depend on the wave's phase);
// the output-error fit does unless ψ is part of its model. A constant phase is already in w0; D = 1
// absorbs a constant frequency offset, D = 2 a frequency ramp.
//
// Internal to the estimator library.

#include <array>
#include <cmath>
#include <complex>
#include <limits>

namespace hrgbench::estimator::internal {

inline constexpr int kMaxPhaseDegree = 3;

class CommonPhase {
 public:
  using Complex = std::complex<double>;

  // `coefficients` holds q_1 … q_degree.
  CommonPhase(const double* coefficients, int degree) noexcept : degree_(degree) {
    for (int j = 0; j < degree_; ++j) q_[static_cast<std::size_t>(j)] = coefficients[j];
  }

  int Degree() const noexcept { return degree_; }

  double Psi(double t) const noexcept {
    double value = 0.0;
    double power = t;
    for (int j = 0; j < degree_; ++j) {
      value += q_[static_cast<std::size_t>(j)] * power;
      power *= t;
    }
    return value;
  }

  // e^{iψ(t)} for the time stamps of a run, called in order. On a uniform grid the D-th difference
  // of a degree-D polynomial is constant, so e^{iψ} advances by D complex products instead of a
  // sincos; it restarts from the closed form every kResync samples and when the step changes (a
  // dropped sample), so rounding stays below ~kResync ulp.
  Complex Next(double t) noexcept {
    if (degree_ == 0) return Complex(1.0, 0.0);
    const double dt = t - last_t_;
    last_t_ = t;
    if (since_sync_ >= kResync || !(std::abs(dt - step_) <= 1e-9 * step_)) {
      step_ = std::isfinite(dt) && dt > 0.0 ? dt : 0.0;
      Resync(t);
      return factor_[0];
    }
    for (int j = 0; j < degree_; ++j)
      factor_[static_cast<std::size_t>(j)] *= factor_[static_cast<std::size_t>(j + 1)];
    ++since_sync_;
    return factor_[0];
  }

 private:
  static constexpr int kResync = 64;

  // factor_[j] = e^{i·Δ^jψ(t)} with forward differences of step step_.
  void Resync(double t) noexcept {
    std::array<double, kMaxPhaseDegree + 1> diff{};
    for (int i = 0; i <= degree_; ++i)
      diff[static_cast<std::size_t>(i)] = Psi(t + static_cast<double>(i) * step_);
    for (int j = 0; j <= degree_; ++j) {
      factor_[static_cast<std::size_t>(j)] = std::polar(1.0, diff[0]);
      for (int i = 0; i < degree_ - j; ++i)
        diff[static_cast<std::size_t>(i)] =
            diff[static_cast<std::size_t>(i + 1)] - diff[static_cast<std::size_t>(i)];
    }
    since_sync_ = 0;
  }

  int degree_ = 0;
  std::array<double, kMaxPhaseDegree> q_{};
  std::array<Complex, kMaxPhaseDegree + 1> factor_{};
  double last_t_ = std::numeric_limits<double>::quiet_NaN();
  double step_ = 0.0;
  int since_sync_ = 0;
};

}  // namespace hrgbench::estimator::internal
