#pragma once
// A starting point for each run's common phase ψ(t) = q_1·t + … + q_D·t^D (common_phase.hpp), from
// the data, before Levenberg–Marquardt.
//
// Why: the starting point of (δ, ξ) comes from the integral equation error, whose forms z do not
// see ψ; a fit that starts ψ at zero sees a run whose reference is 0.06 rad/s off as data turned by
// 6 rad at 100 s (and a 1 mHz/s drift by 30 rad at 100 s). Gauss–Newton then starts in a region
// where the model is nowhere near linear in q, and lands in a wrong basin (a run's drift of the
// wrong sign, τ off by half: issue 23). 20 s runs are short enough for the zero start; 50–200 s
// runs are not.
//
// How: on a decimated grid of the run (at most kPhaseStartPoints time stamps: 0.1 s apart on a
// 200 s run, which reads a residual common frequency of up to 15 rad/s without aliasing; 3 ms of
// CPU for the production session, where one pass over the data takes 20 ms),
//  1. the observed initial state w0 from the first samples, where ψ is still small (a least-squares
//     fit of the model's free run with ψ = 0 over them);
//  2. the model's prediction v(t) = G·exp(A·t)·G⁻¹·w0 at the starting (δ, ξ), without ψ;
//  3. the orbit phase of data and model: u1² + u2² = e^{2iφ}·(a² − b²) for u = (y1 + i·y2,
//     y3 + i·y4) whatever the wave angle θ, so h(t) = (u1² + u2²)·conj(v1² + v2²) turns at 2ψ(t)
//     alone: the wave's precession and the model's own phase evolution (splits, quadrature) are
//     removed, and an error of the predicted wave angle (a few per cent of δ2 from the start turns
//     θ by radians over 100 s) does not matter. |h| ≈ (a² − b²)², so where an orbit is near
//     circular the phase is weighted down instead of read from noise;
//  4. 2ψ̇ from the lag products h_k·conj(h_{k−1}) summed over blocks (no unwrapping: a near-zero
//     |h| costs its block weight, never a 2π slip), fitted by a polynomial of degree D − 1; then
//     2ψ itself refined on the turned-back phase arg(h·e^{−2iψ̂}), now small, with samples more than
//     1 rad off given no weight.
// The constant of ψ is w0's, not q's, and is dropped. Where the data carry no phase (no signal)
// the start is zero, as before.
//
// Internal to the estimator library.

#include "hrgbench/estimator/run_data.hpp"
#include "output_error_problem.hpp"

namespace hrgbench::estimator::internal {

inline constexpr int kPhaseStartPoints = 2000;

// q_1 … q_degree (rad/s^j) into `q` for the run at (p, Ω = run.omega_rad_s + omega_offset_rad_s).
// False (q zero) when the data give no usable phase.
bool StartCommonPhase(const RunData& run, double omega_offset_rad_s, const FullParameters& p,
                      int degree, double* q);

// Each run's nuisance vector as `model` lays it out: w0 zero (SolveInitialStates solves it), the
// common phase from StartCommonPhase, ΔΩ zero. Runs are spread over `threads`.
std::vector<RunNuisance> StartNuisance(const RunSet& runs, const FullParameters& p,
                                       const NuisanceModel& model, int threads);

}  // namespace hrgbench::estimator::internal
