#pragma once
// Which parameters a run plan can determine, decided before any fit.
//
// Structure (docs/estimator/model.md): δ2 enters only through 2Ωδ2, so it needs a run with Ω ≠ 0.
// To first order a pick-off distortion looks like an Ω-proportional anisotropy, (δ3…δ6)_eff =
// (δ3 − 4Ωδ2ξ4, δ4 + 4Ωδ2ξ1, δ5 + 4Ωδ2ξ3, δ6 − 4Ωδ2ξ2), so ξ needs at least two distinct Ω with
// δ2Ω ≠ 0 somewhere. On top of these rules the numerical rank of the (scaled) Fisher information at
// a nominal point catches what the rules miss: a near-null direction names the parameters it
// involves.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "hrgbench/estimator/parameters.hpp"

namespace hrgbench::estimator {

struct IdentifiabilityOptions {
  // Two rates closer than this are one rate: table rate noise is far above 1e-9 rad/s, a distinct
  // set point is far above it.
  double distinct_omega_tol_rad_s = 1e-9;
  // Largest acceptable condition number of the Fisher information scaled to unit diagonal. The
  // paper's design has ~3e4 (ξ weakly determined, still identifiable); exact degeneracy gives
  // ~1e16 or more. 1e10 leaves 6 digits of a double for the solution.
  double max_condition = 1e10;

  bool IsValid(std::string* why) const;
};

struct IdentifiabilityReport {
  std::array<bool, 6> delta_identifiable = {true, true, true, true, true, true};
  XiMask xi_identifiable = kAllXi;
  int distinct_omegas = 0;
  bool has_nonzero_omega = false;
  double condition_number = kNaN;    // of the scaled information of what remains; NaN if unknown
  std::vector<std::string> reasons;  // one sentence per finding, for the operator

  // True when every requested ξ and every δ are identifiable.
  bool AllIdentifiable(const XiMask& requested) const;
  // The requested ξ components that remain identifiable.
  XiMask IdentifiableXi(const XiMask& requested) const;
};

// The structural check from the run rates alone (no data needed).
IdentifiabilityReport CheckRatePlan(const std::vector<double>& omegas_rad_s,
                                    const XiMask& requested,
                                    const IdentifiabilityOptions& options = {});

// The numerical check: `information` is the Fisher information (JᵀJ, any positive scale) of the
// free parameters listed by `delta_free` then `xi_free` (in index order), with nuisance parameters
// already eliminated. Parameters that span near-null directions (condition above max_condition) are
// marked unidentifiable in `report`, with a reason; returns the condition number of what remains.
double CheckInformation(const Eigen::MatrixXd& information, const std::array<bool, 6>& delta_free,
                        const XiMask& xi_free, const IdentifiabilityOptions& options,
                        IdentifiabilityReport* report);

}  // namespace hrgbench::estimator
