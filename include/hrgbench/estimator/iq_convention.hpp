#pragma once
// The demodulation's sign convention: which way the quadrature channels point.
//
// The model (physical_parameters.hpp) demodulates each pick-off channel s_c against the reference
// phase ψ as u_c = 2·LPF[s_c·e^{−iψ}], i.e.
//   y_I = 2·LPF[s_c·cos ψ],  y_Q = −2·LPF[s_c·sin ψ]          ("minus-sine", the model's)
// Much electronics use the other common convention,
//   y_I = 2·LPF[s_c·cos ψ],  y_Q = +2·LPF[s_c·sin ψ]          ("plus-sine")
// which delivers the complex conjugate of each channel. Conjugation is an exact symmetry of the
// free-run model: conjugate data are exactly data of the model with δ5, δ6, ξ2, ξ3 of the opposite
// sign (the frequency axis turned by 45°, the phase mismatch and cross-talk negated), the
// quadrature K = 2ab and the phase negated, and δ1, δ2, δ3, δ4, ξ1, ξ4 and the wave angle θ
// unchanged (the Coriolis term 2Ωδ2·iσy is real). So the fit is perfect and wrong, and nothing
// in a free run's dynamics can tell: the wave does NOT turn the other way. Hence the convention
// is declared by the electronics, recorded in the session and undone before any fit
// (ToModelConvention); what can tell is a sign fixed outside the free run, the quadrature the
// bench commanded at release (bench/recorded_runs.hpp: a fitted K of the opposite sign to the
// plan's names the convention).
//
// Pure inline functions (the session library uses them and links no estimator code), Eigen and
// the standard library only; noexcept; no allocation.

#include <Eigen/Core>
#include <optional>
#include <string_view>

namespace hrgbench::estimator {

enum class IqConvention {
  kMinusSine,  // y_Q = −2·LPF[s·sin ψ]: u = 2·LPF[s·e^{−iψ}], the model's
  kPlusSine,   // y_Q = +2·LPF[s·sin ψ]: the complex conjugate of the model's
};

// "minus-sine", "plus-sine": the names the session and the config files use.
inline std::string_view IqConventionName(IqConvention convention) noexcept {
  return convention == IqConvention::kPlusSine ? "plus-sine" : "minus-sine";
}
// The convention of a name above; nullopt for anything else.
inline std::optional<IqConvention> ParseIqConvention(std::string_view name) noexcept {
  if (name == "minus-sine") return IqConvention::kMinusSine;
  if (name == "plus-sine") return IqConvention::kPlusSine;
  return std::nullopt;
}

// Brings the samples y (4 × n: y1..y4) of a run recorded in `convention` into the model's:
// nothing for minus-sine; for plus-sine each channel's complex sample conjugated (y2 and y4
// negated).
inline void ToModelConvention(IqConvention convention, Eigen::Ref<Eigen::Matrix4Xd> y) noexcept {
  if (convention != IqConvention::kPlusSine) return;
  // conj(y1 + i·y2) = y1 − i·y2: the quadrature rows change sign, the in-phase rows stay.
  y.row(1) = -y.row(1);
  y.row(3) = -y.row(3);
}

// A fitted angular gain δ2 more than this many of its std below zero names the sign of the
// recorded rates as the likely cause (maximum_likelihood.cpp). Far from any real resonator
// (δ2 ≈ 0.3 with a relative std of 1e-7 … 1e-2), and far from chance (5 std).
inline constexpr double kNegativeAngularGainInStd = 5.0;

}  // namespace hrgbench::estimator
