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
    for (int j = 0; j < degree_; ++j) {
      q_[static_cast<std::size_t>(j)] = coefficients[j];
      zero_ = zero_ && coefficients[j] == 0.0;
    }
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
    // A zero phase (every fit's start) is 1 exactly, as the recurrence would give it.
    if (degree_ == 0 || zero_) return Complex(1.0, 0.0);
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
  bool zero_ = true;  // every q_j is 0
  static constexpr int kResync = 64;

  // factor_[j] = e^{i·Δ^jψ(t)} with forward differences of step step_. The differences are taken
  // on the polynomial's coefficients (binomial expansion of ψ(t + h) − ψ(t)), not by subtracting
  // values of ψ, which would cancel all but a few digits of Δ³ψ = 6·q3·h³.
  // Out of line and cold, so that Next's common path is small enough to inline into every pass's
  // sample loop (it was called per sample).
  [[gnu::noinline, gnu::cold]] void Resync(double t) noexcept {
    std::array<double, kMaxPhaseDegree + 1> c{};  // ψ(t) = Σ c[m]·t^m, c[0] = 0
    for (int j = 1; j <= degree_; ++j)
      c[static_cast<std::size_t>(j)] = q_[static_cast<std::size_t>(j - 1)];
    int top = degree_;
    for (int j = 0; j <= degree_; ++j) {
      double value = 0.0;
      for (int m = top; m >= 0; --m) value = value * t + c[static_cast<std::size_t>(m)];
      factor_[static_cast<std::size_t>(j)] = std::polar(1.0, value);
      // c ← Δc: d[m] = Σ_{k>m} c[k]·C(k, m)·h^{k−m}.
      std::array<double, kMaxPhaseDegree + 1> d{};
      for (int m = 0; m < top; ++m) {
        double binomial = 1.0;  // C(k, m), starting at k = m
        double power = 1.0;     // h^{k−m}
        for (int k = m + 1; k <= top; ++k) {
          binomial = binomial * k / (k - m);
          power *= step_;
          d[static_cast<std::size_t>(m)] += c[static_cast<std::size_t>(k)] * binomial * power;
        }
      }
      c = d;
      --top;
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
