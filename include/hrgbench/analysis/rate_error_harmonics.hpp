#pragma once
// The angle-dependent rate error of a whole-angle gyro on the table (issue 28 §3): the gyro's rate
// output minus the table's rate, as a function of the wave's electrical angle θ while the wave
// turns under a constant rate, read as a bias plus harmonics of 2θ (the period of every form of the
// wave: docs/estimator/operating-mode.md):
//
//   Ω̂ − Ω = b + Σ_{n=1}^{N} (c_n·cos 2nθ + s_n·sin 2nθ) + noise.
//
// The samples are first averaged in consecutive windows (the rate of a window is its angle's
// increment over its length, so the angle's white readout noise falls as 1/window), then fitted by
// least squares on the windows' mean angles. The std are the fit's with the residuals' own scatter,
// taking the windows as independent: two windows that share an end share its angle noise, which
// makes neighbouring windows' errors anti-correlated; the stated std then errs on the large side
// for the bias and the low harmonics. The angle should cover whole turns of 2θ, or the harmonics
// and the bias are not orthogonal (the fit still separates them; their std say how well). Pure;
// allocates its result.

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace hrgbench::analysis {

struct RateErrorHarmonics {
  bool ok = false;
  std::string why;  // when not ok: what was missing
  double bias_rad_s = 0.0;
  double bias_std_rad_s = 0.0;
  // Index n − 1 holds the coefficients of cos 2nθ and sin 2nθ.
  std::vector<double> cos_rad_s, sin_rad_s, cos_std_rad_s, sin_std_rad_s;
  // √(Σ (c_n² + s_n²)/2): the RMS over a turn of the angle-dependent part (the paper's criterion's
  // norm, taken over the angle).
  double angle_dependent_rms_rad_s = 0.0;
  double residual_rms_rad_s = 0.0;  // what the harmonics leave, per window
  double angle_span_rad = 0.0;      // how far 2θ turned over the windows, rad
  std::size_t windows = 0;
};

// `angle_rad` θ̂ (electrical, unwrapped) and `rate_error_rad_s` Ω̂ − Ω per sample, equal lengths;
// `window` samples per window (≥ 1); `harmonics` N in 1 … 8. Needs at least 2N + 3 windows.
RateErrorHarmonics FitRateErrorHarmonics(std::span<const double> angle_rad,
                                         std::span<const double> rate_error_rad_s,
                                         std::size_t window, int harmonics);

}  // namespace hrgbench::analysis
