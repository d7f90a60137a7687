#pragma once
// The estimate in the units a gyro engineer reads: decay times and Q, the frequency and damping
// splits with their axes on the shell, the angular gain (Bryan's factor), and the pick-off path's
// gain and phase mismatch, cross-talk and electrode angle; each with its standard error from the
// estimate's full covariance (delta method).
//
// ## Definitions (physical_parameters.hpp derives the maps; the README states the conventions)
//   resonant_frequency_hz  f0, as the electronics report it (not estimated: given by the caller)
//   tau_s                  τ = −1/δ1, the mean amplitude decay time (1/τ is the mean of the two
//                          modes' decay rates)
//   q_factor               Q = π·f0·τ
//   tau1_s, tau2_s         the decay times of the two free modes, from the eigenvalues of
//                          A(0, δ) = δ1·I + (δ3 + iδ5)·σz + (δ4 + iδ6)·σx, exactly: δ1 ± λ with
//                          λ² = (δ3 + iδ5)² + (δ4 + iδ6)²; τ1 the slower mode (τ1 ≥ τ2). When the
//                          damping and frequency axes differ, the modes mix both anisotropies, so
//                          1/τ2 − 1/τ1 ≤ Δ(1/τ): the split a wave shows, not the damping's own.
//   damping_split_per_s    Δ(1/τ) = 2·|δ3 + iδ4|: the damping anisotropy of the shell (the
//                          difference of the decay rates of its principal axes), 1/s
//   damping_axis_deg       θ_τ on the shell: the axis that decays FASTER, in (−45°, 45°]
//   frequency_split_mhz    Δf = |δ5 + iδ6|/π, mHz (exact in the eigenvalues when the damping is
//                          isotropic; to (Δ(1/τ)/(2πΔf))² otherwise)
//   frequency_axis_deg     θ_ω on the shell: the axis of the HIGHER frequency, in (−45°, 45°]
//   angular_gain           k = δ2 (Bryan's factor): the wave on the shell precesses at −k·Ω
//                          relative to the case, i.e. it turns by (1 − k)·Ω in inertial space
//   gain_mismatch_percent  (g2/g1 − 1)·100: channel 2's gain relative to channel 1's
//   phase_mismatch_deg     φ2 − φ1 at the carrier, degrees of carrier phase (channel 2 lags more)
//   cross_talk_percent     κ·100: each channel's pick-up of the other electrode, 90° late
//   electrode_angle_deg    ε/2 on the shell: the electrodes are 45° − ε/2 apart (45° ideal)
//
// ANGLES ON THE SHELL. The model's angles (the wave angle θ, θ_ω, θ_τ, ε) are electrical angles of
// the n = 2 mode: channel 2's electrode sits at 90° in the model's frame and at 45° on the shell.
// A wave turned by α on the shell turns by 2α in the model. Every *_deg angle here is on the shell,
// half the model's, measured from channel 1's electrode towards channel 2's; an n = 2 axis is
// defined modulo 90° on the shell, so axes are folded into (−45°, 45°].
//
// ## Uncertainties
// std = √(J·Σ·Jᵀ), J by central differences of the exact maps at steps of 1e-3 std of each
// estimated parameter (so the derivative is the one over the covariance's own scale), Σ the
// summary's covariance (white or sandwich). Held parameters contribute nothing; a quantity that
// depends on a held or missing parameter is not determined (its value is the held one's image).
//
// ## Undetermined axes
// An axis is meaningless when its split is noise: the split vector (δ5, δ6) (or (δ3, δ4)) is tested
// against zero with its 2×2 covariance, d² = vᵀ·Σv⁻¹·v ~ χ²(2) under zero split; below
// `axis_significance_chi2` (default −2·ln 0.0027 = 11.83, the two-sided 3σ level of one
// dimension) the axis is reported undetermined: value NaN, determined = false, and a note.
//
// Pure functions; allocate (not for a real-time loop); never throw except std::bad_alloc.

#include <array>
#include <cstddef>
#include <string>
#include <string_view>

#include "hrgbench/estimator/parameters.hpp"
#include "hrgbench/estimator/summary.hpp"

namespace hrgbench::estimator {

enum class EngineeringQuantity : int {
  kResonantFrequency,
  kDecayTime,
  kQualityFactor,
  kSlowModeDecayTime,
  kFastModeDecayTime,
  kDampingSplit,
  kDampingAxis,
  kFrequencySplit,
  kFrequencyAxis,
  kAngularGain,
  kPickoffGainMismatch,
  kPickoffPhaseMismatch,
  kPickoffCrossTalk,
  kElectrodeAngle,
};
inline constexpr std::size_t kEngineeringQuantityCount = 14;

struct EngineeringQuantityInfo {
  std::string_view name;   // key in limits files, JSON and the record: "tau_s"
  std::string_view label;  // for people: "mean decay time τ"
  std::string_view unit;   // "s", "mHz", "deg", "%", "" (dimensionless)
};
inline constexpr std::array<EngineeringQuantityInfo, kEngineeringQuantityCount>
    kEngineeringQuantities = {{
        {"resonant_frequency_hz", "resonant frequency f0", "Hz"},
        {"tau_s", "mean decay time τ", "s"},
        {"q_factor", "quality factor Q", ""},
        {"tau1_s", "slow mode decay time τ1", "s"},
        {"tau2_s", "fast mode decay time τ2", "s"},
        {"damping_split_per_s", "damping split Δ(1/τ)", "1/s"},
        {"damping_axis_deg", "damping axis θτ (faster decay, on the shell)", "deg"},
        {"frequency_split_mhz", "frequency split Δf", "mHz"},
        {"frequency_axis_deg", "frequency axis θω (higher frequency, on the shell)", "deg"},
        {"angular_gain", "angular gain k (Bryan factor)", ""},
        {"gain_mismatch_percent", "pick-off gain mismatch g2/g1 − 1", "%"},
        {"phase_mismatch_deg", "pick-off phase mismatch φ2 − φ1", "deg"},
        {"cross_talk_percent", "pick-off cross-talk κ", "%"},
        {"electrode_angle_deg", "electrode angle error (on the shell)", "deg"},
    }};

const EngineeringQuantityInfo& Info(EngineeringQuantity quantity) noexcept;

// Whether a quantity depends on parameter `index` of (δ1 … δ6, ξ1 … ξ4) (0-based, δ1 = 0, ξ1 = 6):
// it is determined only when every parameter it depends on was estimated.
bool DependsOn(EngineeringQuantity quantity, int index) noexcept;

struct EngineeringValue {
  double value = kNaN;
  double std = kNaN;        // one standard error; NaN when not determined or no covariance
  bool determined = false;  // false: a parameter it needs was held or missing, or an axis of an
                            // insignificant split (value NaN then), or not finite
  std::string note;         // why not determined, or a caveat ("split not significant")
};

struct EngineeringOptions {
  // χ²(2) threshold below which a split is "not significantly different from zero" and its axis
  // is undetermined (default: the 3σ two-sided level, p = 0.0027).
  double axis_significance_chi2 = 11.829;
};

struct EngineeringQuantities {
  double frequency_hz = kNaN;  // the f0 they were computed with (NaN: unknown, so Q is too)
  std::array<EngineeringValue, kEngineeringQuantityCount> values;

  const EngineeringValue& operator[](EngineeringQuantity q) const noexcept {
    return values[static_cast<std::size_t>(q)];
  }
  EngineeringValue& operator[](EngineeringQuantity q) noexcept {
    return values[static_cast<std::size_t>(q)];
  }
  // A table: one line per quantity, "label  value ± std unit", notes after.
  std::string Report() const;
};

// From an estimate (δ, ξ, which were estimated, and the covariance) and f0 (Hz; NaN if unknown).
// An unusable summary gives values from whatever δ, ξ hold, none determined.
EngineeringQuantities ComputeEngineeringQuantities(const EstimateSummary& summary,
                                                   double frequency_hz,
                                                   const EngineeringOptions& options = {});

// The values alone (no std, no significance), from a full parameter set: the exact maps, for
// tests and for the delta method. Angles on the shell in degrees, as above.
std::array<double, kEngineeringQuantityCount> EngineeringValues(const Delta& delta, const Xi& xi,
                                                                double frequency_hz) noexcept;

}  // namespace hrgbench::estimator
