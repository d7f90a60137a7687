#pragma once
// The HRG free-run model in matrix form, exactly as verified in docs/estimator/model.md:
//   dx/dt = A(Ω, δ)·x,   y = (I + C(ξ))·x,   z = W(x)·x = (Ac, As, K, S),
//   dz/dt = 2·M(Ω, δ)·z = 2·Mδ(Ω, z)·δ.
// Ω is the angular rate about the sensitive axis in rad/s. All functions are pure, allocation-free
// and noexcept; none of them validates its input (NaN in, NaN out).

#include "hrgbench/estimator/parameters.hpp"

namespace hrgbench::estimator {

using Matrix4 = Eigen::Matrix4d;
using Matrix46 = Eigen::Matrix<double, 4, 6>;

// Orbit elements of the standing wave: a amplitude, b quadrature, θ wave angle [rad], φ phase
// [rad].
struct Orbit {
  double a = 0.0;
  double b = 0.0;
  double theta_rad = 0.0;
  double phi_rad = 0.0;
};

// System matrix A(Ω, δ) of the free run (the paper's third row corrected, model.md "Matrices").
Matrix4 SystemMatrix(double omega_rad_s, const Delta& delta) noexcept;

// Pick-off distortion C(ξ); the observation is y = (I + C)·x.
Matrix4 DistortionMatrix(const Xi& xi) noexcept;

// W(x), with z = W(x)·x and W(a)·b = W(b)·a.
Matrix4 FormsMatrix(const State& x) noexcept;

// z = (Ac, As, K, S) = W(x)·x.
Forms QuadraticForms(const State& x) noexcept;

// M(Ω, δ) with dz/dt = 2·M·z.
Matrix4 FormsDynamics(double omega_rad_s, const Delta& delta) noexcept;

// Mδ(Ω, z) with dz/dt = 2·Mδ(Ω, z)·δ (linear in δ: the basis of every equation-error method).
Matrix46 FormsRegressor(double omega_rad_s, const Forms& z) noexcept;

// The paper's first-order distortion of the forms: z ≈ N(ξ)·r = r + Nξ(r)·ξ with r = W(y)·y
// (the printed "ξ5" read as ξ4 and the "−As" as −2As: docs/estimator/model.md, "Distortion of
// the pick-off path in z").
Matrix4 FirstOrderFormsDistortion(const Xi& xi) noexcept;     // N(ξ)
Matrix4 FirstOrderFormsSensitivity(const Forms& r) noexcept;  // Nξ(r)

// The paper's special-case regressor Mδ(Ω, r, λ, φ) for ξ = (λ, φ, 0, 0), with the δ2 column
// corrected (model.md "The paper's method"): dr/dt ≈ 2·Mδ(Ω, r, λ, φ)·δ to first order in ξ.
Matrix46 FirstOrderFormsRegressor(double omega_rad_s, const Forms& r, double lambda,
                                  double phi) noexcept;

// Exact inverse of the distortion: x = (I + C(ξ))⁻¹·y. I + C acts on u = (x1 + i·x2, x3 + i·x4) as
// a complex 2×2 matrix, so the inverse is closed-form; it exists whenever det ≠ 0 (|ξ| < 1/2
// suffices).
State UndistortExact(const Xi& xi, const Observation& y) noexcept;

// x from orbit elements (model.md "State, observation, orbit elements"):
//   x1 = a cosθ cosφ + b sinθ sinφ,  x2 = a cosθ sinφ − b sinθ cosφ,
//   x3 = a sinθ cosφ − b cosθ sinφ,  x4 = a sinθ sinφ + b cosθ cosφ.
State OrbitToState(const Orbit& orbit) noexcept;

// Orbit elements from x, the inverse of OrbitToState with the conventions a ≥ |b| and
// θ ∈ (−π/2, π/2]. The map x → (a, b, θ, φ) is two-to-one ((a, b, θ, φ) and (a, b, θ+π, φ+π) give
// the same x... up to the sign flips the convention removes). Degenerate case a = |b| (a circular
// orbit: Ac = As = 0): θ is not defined; this function then returns θ = 0 and puts the whole angle
// into φ, so OrbitToState(StateToOrbit(x)) == x still holds. x = 0 gives all zeros.
Orbit StateToOrbit(const State& x) noexcept;

}  // namespace hrgbench::estimator
