#pragma once
// The scale factor of a gyro's rate output over a set of constant rates (issue 28 §3; IEEE Std
// 1431-2004 §3 and Annex B's terms): each hold's mean rate error e_i = mean(Ω̂ − Ω) at the table's
// measured Ω_i, with its std, fitted by weighted least squares as
//
//   e(Ω) = b + ε·Ω,
//
// b the bias and ε the scale-factor error (ε·1e6 in ppm); the nonlinearity is the largest residual
// over the largest |Ω| (IEEE 1431's "scale factor nonlinearity", in ppm of full scale), read only
// with a rate more than the line's two (with two it is zero by construction and not reported).
// The stds are the weighted fit's, scaled up by √(χ²/dof) when the residuals say the holds' stds
// are too small (the Birge ratio; never scaled down).
//
// The asymmetry (IEEE 1431's scale-factor asymmetry: the scale factor with positive inputs less the
// one with negative inputs, relative to the scale factor) from the fit e(Ω) = b + ε·Ω + α·|Ω|, so
// that ε± = ε ± α and the asymmetry is ε+ − ε− = 2α; it needs rates of both signs and two distinct
// magnitudes (at ±Ω only, α is the bias's twin and not reported), its std the fit's with its own
// Birge ratio.
// Pure; no allocation beyond the result.

#include <span>
#include <string>

namespace hrgbench::analysis {

struct RateHoldMean {
  double omega_rad_s = 0.0;  // the table's measured rate (unit frame, Earth rate included)
  double error_rad_s = 0.0;  // mean of Ω̂ − Ω over the hold
  double std_rad_s = 0.0;    // its std (> 0)
};

struct ScaleFactorFit {
  bool ok = false;
  std::string why;  // when not ok
  double bias_rad_s = 0.0, bias_std_rad_s = 0.0;
  double scale_factor_error = 0.0, scale_factor_error_std = 0.0;  // dimensionless (×1e6: ppm)
  bool nonlinearity_known = false;                                // three distinct rates or more
  double nonlinearity = 0.0;                    // max |residual| / max |Ω|, dimensionless
  bool asymmetry_known = false;                 // both signs and two distinct |Ω|
  double asymmetry = 0.0, asymmetry_std = 0.0;  // ε+ − ε−, dimensionless (×1e6: ppm)
  double chi2 = 0.0;
  int dof = 0;
};

// Needs two distinct rates at least and every std finite and > 0.
ScaleFactorFit FitScaleFactor(std::span<const RateHoldMean> holds);

}  // namespace hrgbench::analysis
