#pragma once
// Undoing what the demodulation reference did: a run's channels turned back by the reference's
// reported phase, before the fit.
//
// The electronics demodulate each pick-off channel against their reference oscillator,
// u_c = 2·LPF[s_c·e^{−iψ}] with u1 = y1 + i·y2, u2 = y3 + i·y4 (physical_parameters.hpp). The slow
// model assumes ψ = ψ(release) + ω_lock·t, the reference kept at the frequency it was locked to
// at release; the estimator's per-run common phase (q1·t + q2·t²) absorbs a reference that stays
// off that by a constant offset or a ramp. A TRACKING reference (a PLL that follows the wave after
// release) moves ψ by χ(t) = ψ − ω_lock·t, which follows the wave's own phase and is no
// polynomial: y = e^{−iχ(t)}·y_locked, which the slow model cannot fit (drivers/sim/README.md: ~4e3
// reported std). Electronics that report χ with each sample (as seen through their output filter,
// i.e. aligned with the sample) let the bench recover y_locked = e^{+iχ}·y exactly, for each
// channel: (y1, y2) and (y3, y4) each turned by +χ.
//
// When χ is not reported (older electronics), nothing can be undone here: the fit then shows a
// residual far above the noise and coloured residuals, and fit_diagnostics.hpp flags it.
//
// Pure function, Eigen and the standard library only; noexcept; no allocation.

#include <Eigen/Core>
#include <span>

namespace hrgbench::estimator {

// Turns each column k of `y` (4 × n: y1..y4) by χ = reference_phase_rad[k]: (y1, y2) and (y3, y4)
// as complex numbers y1 + i·y2, y3 + i·y4 multiplied by e^{+iχ}. Returns false (and changes
// nothing) when the sizes differ or a χ is not finite.
bool UndoReferencePhase(Eigen::Ref<Eigen::Matrix4Xd> y,
                        std::span<const double> reference_phase_rad) noexcept;

}  // namespace hrgbench::estimator
