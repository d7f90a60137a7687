#pragma once
// The pick-off distortion the slow model sees on a unit with a frequency split: the pick-off's
// own ξ plus a second-order term of the averaging that turns the modes' shapes.
//
// physical_parameters.hpp averages the oscillator q̈ + D·q̇ + K·q + G·q̇ = 0 (G = 4kΩ·J) onto
// u̇ = A1·u, A1 = (i/2ω0)·M with M = iω0·(D + G) + (K − ω0²·I): first order in |A|/ω0. Writing
// u̇ = (i/2ω0)·(M·u + M̄·ū·e^{−2iω0t}) exactly (osculating variables) and averaging to second
// order (near-identity transform w = −M̄·ū·e^{−2iω0t}/(4ω0²), which the output filter removes) adds
//
//     A2 − A1 = −i·M̄·M/(8ω0³) = −i·(ω0²·B² + S²)/(8ω0³) + (S·B − B·S)/(8ω0²),
//
// with B = D + G and S = K − ω0²·I.
//
// The first part is a multiple of I to within Δ(1/τ)-sized terms (G² = −(4kΩ)²·I gives the common
// drift ν = (2kΩ)²/(2ω0), S² the split's Δω²/(8ω0)): a common phase, absorbed per run. The
// commutator is new: with S = ω0·Δω·P(θ_ω) + (Δω²/4)·I and [P(θ), J] = 2·(sin2θ·σz − cos2θ·σx),
//
//     E = [S, G]/(8ω0²) = (kΩ·Δω/ω0)·(sin2θ_ω·σz − cos2θ_ω·σx),
//
// a real traceless term proportional to Ω, which model.md's A (δ3, δ4 do not scale with Ω) has
// not. It is, exactly at this order, a constant change of basis: u = (I + X)·v with v̇ = A1·v
// needs [X, A1] = E, solved by X = −(Δω/(4ω0))·P(θ_ω) = −(δ5·σz + δ6·σx)/(2ω0) (X commutes with
// the split's own i·(δ5·σz + δ6·σx); its commutator with δ3, δ4 is third order). The data are then
// y = (I + C(ξ))·(I + X)·v = (I + C(ξ) + X)·v to second order, and C = ξ1·σz + ξ4·σx − i·(ξ2·σz +
// ξ3·σx) (model.md) takes X up in ξ1 and ξ4:
//
//     ξ1 seen = ξ1 − δ5/(2ω0),   ξ4 seen = ξ4 − δ6/(2ω0),   ξ2, ξ3 unchanged,
//
// whatever Ω and k (the term's Ω-dependence is what the rotation runs see; a design without
// rotation does not see it, but then nothing tells X from the pick-off either). Checked: the
// oscillator's exact eigenstructure (E to 0.5 % at Ω = 0.3, 1 rad/s, Δf = 1 Hz; after X what is
// left is below 5e-7 rad/s, third order), and the carrier
// simulator fitted at Δf = 0.01, 0.1, 1 Hz: ξ1 off by −4.54e-7, −4.62e-6, −4.609e-5 and ξ4 by
// −1.9e-7, −1.90e-6, −1.940e-5 from the pick-off's, against −4.61e-7·(1, 10, 100) and
// −1.95e-7·(1, 10, 100) from this formula (θ_ω = 0.2, f0 = 5 kHz; drivers/sim/README.md).
// On a trimmed resonator (Δf = 0.2 mHz) the term is 9e-9: far below the noise.
//
// Pure functions, noexcept, no validation (frequency_hz > 0 is the caller's).

#include "hrgbench/estimator/parameters.hpp"

namespace hrgbench::estimator {

// The ξ an output-error fit of the slow model finds on a unit with pick-off ξ `pickoff_xi`,
// split terms δ5, δ6 of `delta` (rad/s) and carrier frequency `frequency_hz` (f0, Hz).
Xi XiSeenBySlowModel(const Xi& pickoff_xi, const Delta& delta, double frequency_hz) noexcept;

// The inverse: the pick-off's own ξ from a fitted ξ and δ (the fitted δ5, δ6 serve: the term is
// second order).
Xi PickoffXiFromSlowModel(const Xi& fitted_xi, const Delta& delta, double frequency_hz) noexcept;

}  // namespace hrgbench::estimator
