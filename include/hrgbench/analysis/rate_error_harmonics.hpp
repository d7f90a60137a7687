#pragma once
// The angle-dependent rate error of a whole-angle gyro on the table (issue 28 §3): the gyro's rate
// output minus the table's rate, as a function of the wave's electrical angle θ while the wave
// turns under a constant rate, read as a bias plus harmonics of 2θ (the period of every form of the
// wave: docs/estimator/operating-mode.md):
//
//   Ω̂ − Ω = b + Σ_{n=1}^{N} (c_n·cos 2nθ + s_n·sin 2nθ) + noise.
//
// How it is fitted depends on the noise that dominates, which the caller names (as for the Allan
// deviation):
//   - white angle noise (the pick-off's noise read through the angle: each rate sample is a
//     difference of two noisy angles, so neighbouring rates are anti-correlated): the fit is made
//     on the integrated error, the gyro's angle against the table's, E_k = h·Σ_{i≤k}(Ω̂_i − Ω),
//     whose noise is the angle's own and white, with the regressors integrated alike (h·k for the
//     bias, h·Σ cos 2nθ_i, h·Σ sin 2nθ_i) and a free constant;
//   - white rate noise (angle random walk): the fit is made on the mean rate of each window.
// Either way the samples are averaged in windows of `window` first (the regressors vary slowly over
// a window) and the std are least squares' with the residuals' own scatter, windows taken as
// independent, which holds for the named noise. Under the other noise they are wrong: fitted as
// white angle, a rate random walk's std are understated; fitted as white rate, an angle noise's are
// overstated by up to √windows. The angle should cover whole turns of 2θ, or the harmonics and the
// bias are not orthogonal (the fit still separates them; their std say how well).
// Pure; allocates its result.

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace hrgbench::analysis {

enum class RateErrorNoise {
  kWhiteAngle,  // the pick-off's noise through the angle readout (the simulated bench's case)
  kWhiteRate,   // angle random walk
};

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
  // What the fit leaves per window: rad (the integrated error) for white angle noise, rad/s (the
  // window's rate) for white rate noise.
  double residual_rms = 0.0;
  double angle_span_rad = 0.0;  // how far 2θ turned over the windows, rad
  std::size_t windows = 0;
};

// `angle_rad` θ̂ (electrical, unwrapped) and `rate_error_rad_s` Ω̂ − Ω per sample, equal lengths,
// the rate of sample k being over the period that ends at it; `sample_period_s` h > 0; `window`
// samples per window (≥ 1); `harmonics` N in 1 … 8. Needs at least 2N + 4 windows.
RateErrorHarmonics FitRateErrorHarmonics(std::span<const double> angle_rad,
                                         std::span<const double> rate_error_rad_s,
                                         double sample_period_s, std::size_t window, int harmonics,
                                         RateErrorNoise noise = RateErrorNoise::kWhiteAngle);

}  // namespace hrgbench::analysis
