#pragma once
// The estimate in the units a gyro engineer reads: decay times and Q, the frequency and damping
// splits with their axes on the shell, the angular gain (Bryan's factor), and the pick-off path's
// gain and phase mismatch, cross-talk and electrode angle; each with its standard error from the
// estimate's full covariance (delta method).
//
// ## Definitions (physical_parameters.hpp derives the maps; docs/estimator/engineering-units.md
// states the conventions)
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
//                          isotropic; to (Δ(1/τ)/(2πΔf))² otherwise); like f0 it follows the
//                          temperature: the runs' mean split, at their mean temperature
//   frequency_axis_deg     θ_ω on the shell: the axis of the HIGHER frequency, in (−45°, 45°]
//   angular_gain           k = δ2 (Bryan's factor): the wave on the shell precesses at −k·Ω
//                          relative to the case, i.e. it turns by (1 − k)·Ω in inertial space
//   gain_mismatch_percent  (g2/g1 − 1)·100: channel 2's gain relative to channel 1's
//   phase_mismatch_deg     φ2 − φ1 at the carrier, degrees of carrier phase (channel 2 lags more)
//   cross_talk_percent     κ·100: each electrode line's pick-up of the other's signal, 90° late
//   electrode_angle_deg    ε/2 on the shell: channel 2's electrode sits 45° − ε/2 from channel 1's
//
// ## Each quantity is the physical one
// The fit's (δ, ξ) are the model's; three steps make them the unit's (EngineeringModel):
//  1. The split's Coriolis mixing is taken out of ξ (split_coriolis_mixing.hpp, f0 given): the
//     pick-off's own ξ.
//  2. The physical pick-off (g, Δφ, κ, ε) whose H has that ξ under the nominal pick-off model,
//     and its complex frame angle a (pickoff_frame.hpp); the anisotropies are turned by −2a into
//     channel 1's electrode frame. So every axis is measured from channel 1's electrode, and the
//     damping split is free of the frequency split the pick-off's antisymmetric coupling mixes
//     into it.
//  3. δ1 is corrected for each run's fitted frequency drift (the common phase's 2·q2, as ω̇/ω0):
//     the displacement of a resonator whose frequency moves decays at an extra ½·ω̇/ω
//     (frequency_drift_decay.hpp), which is not damping.
//
// ANGLES ON THE SHELL. The model's angles (the wave angle θ, θ_ω, θ_τ, ε) are electrical angles of
// the n = 2 mode: channel 2's electrode sits at 90° in the model's frame and at 45° on the shell.
// A wave turned by α on the shell turns by 2α in the model. Every *_deg angle here is on the shell,
// half the electrical one, measured from channel 1's electrode towards channel 2's; an n = 2 axis
// is defined modulo 90° on the shell, so axes are folded into (−45°, 45°].
//
// ## The uncertainty budget (GUM, JCGM 100 §8)
// Each determined quantity carries its components (UncertaintyComponent, in its own unit):
//   fit (statistical)   √(J·Σ·Jᵀ), J by central differences of the whole map above at 1e-3 std of
//                       each estimated parameter, Σ the summary's covariance (white or sandwich);
//                       the recorded Ω uncertainty (a prior of the fit) and the declared noise
//                       shape are inside it, and its note says so;
//   pick-off model      what the physics of the pick-off does not fix: the cross-talk's stage
//                       (midway, and the distance to either end as a rectangular half-width)
//                       and an antisymmetric coupling beyond the model within a declared bound
//                       (EngineeringOptions::unmodelled_coupling_bound_rad), both free runs cannot
//                       see (pickoff_frame.hpp);
//   frequency drift     the spread of the runs' drift corrections (the fit's δ1 is a weighted mean
//                       of theirs, with weights it does not report); for the frequency split, how
//                       far it moves with f over the longest run (Δf·|ω̇/ω0|·T, rectangular);
//   f0 as reported      the electronics' f0 uncertainty, when stated.
// A component a session cannot evaluate is listed with a NaN size and a note saying why; the
// combined standard uncertainty u_c (std) is the root sum of squares of the evaluated ones, and
// std·coverage_factor is the expanded uncertainty (k = 2: about 95 % for a normal distribution).
// The verdict judges std (u_c).
//
// ## Undetermined axes
// An axis is meaningless when its split is noise: the split vector (δ5, δ6) (or (δ3, δ4)) is tested
// against zero with its 2×2 covariance, d² = vᵀ·Σv⁻¹·v ~ χ²(2) under zero split; below
// `axis_significance_chi2` (default −2·ln 0.0027 = 11.83, the two-sided 3σ level of one
// dimension) the axis is reported undetermined: value NaN, determined = false, and a note.
//
// Pure functions; allocate (not for a real-time loop); never throw except std::bad_alloc.

#include <array>
#include <complex>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "hrgbench/estimator/parameters.hpp"
#include "hrgbench/estimator/pickoff_frame.hpp"
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

// One line of a quantity's uncertainty budget.
struct UncertaintyComponent {
  std::string source;  // "fit (statistical)", "pick-off model: cross-talk stage", ...
  double standard_uncertainty = kNaN;  // in the quantity's unit; NaN: not evaluated (note says why)
  bool systematic = false;             // type B: not reduced by more data of this session's kind
  std::string note;                    // how it was evaluated, or why it could not be
};

struct EngineeringValue {
  double value = kNaN;
  double std = kNaN;              // combined standard uncertainty u_c; NaN when not determined
  double statistical_std = kNaN;  // the fit's statistical component alone
  bool determined = false;  // false: a parameter it needs was held or missing, or an axis of an
                            // insignificant split (value NaN then), or not finite
  std::string note;         // why not determined, or a caveat ("split not significant")
  std::vector<UncertaintyComponent> budget;  // largest first; the unevaluated ones last
};

struct EngineeringOptions {
  // χ²(2) threshold below which a split is "not significantly different from zero" and its axis
  // is undetermined (default: the 3σ two-sided level, p = 0.0027).
  double axis_significance_chi2 = 11.829;
  // Where the pick-off's cross-talk sits (pickoff_frame.hpp): kMidway when it is not known, and
  // the budget carries the distance to either end; a stage the station declares carries none.
  CrossTalkStage cross_talk_stage = CrossTalkStage::kMidway;
  // A bound on the pick-off's antisymmetric coupling beyond the model, rad (electrical; each of
  // Re a and Im a within ±bound, rectangular). 0: none declared (the budget says so).
  double unmodelled_coupling_bound_rad = 0.0;
  // f0's standard uncertainty, Hz (NaN: not stated, taken exact), and where it came from.
  double frequency_std_hz = kNaN;
  std::string frequency_std_source = "the electronics' statement";
  double coverage_factor = 2.0;  // k of the expanded uncertainty U = k·u_c
  // The longest run's free run, s (NaN: unknown): the splits follow f over it under a drift.
  double longest_run_s = kNaN;
};

// How the fitted (δ, ξ) become the unit's physical quantities (see "Each quantity is the
// physical one"): the inputs of the map besides δ and ξ.
struct EngineeringModel {
  double frequency_hz = kNaN;  // f0 (NaN: unknown: Q undetermined, the Coriolis mixing stays in ξ)
  // ω̇/ω0 the runs' common phases measured (1/s); δ1 is corrected by +½ of it.
  double relative_frequency_rate_per_s = 0.0;
  CrossTalkStage cross_talk_stage = CrossTalkStage::kMidway;
  // Added to the pick-off's frame angle: an unmodelled antisymmetric coupling (budget only).
  std::complex<double> frame_angle_offset_rad = 0.0;
};

struct EngineeringQuantities {
  double frequency_hz = kNaN;  // the f0 they were computed with (NaN: unknown, so Q is too)
  std::array<EngineeringValue, kEngineeringQuantityCount> values;
  double coverage_factor = 2.0;
  // What the map used: the drift correction (NaN: not corrected) and the nominal pick-off.
  double relative_frequency_rate_per_s = kNaN;
  CrossTalkStage cross_talk_stage = CrossTalkStage::kMidway;
  std::complex<double> pickoff_frame_angle_rad = kNaN;  // a of the nominal pick-off, electrical
  // What free runs cannot separate, and how each quantity got around it: for people.
  std::vector<std::string> limitations;

  const EngineeringValue& operator[](EngineeringQuantity q) const noexcept {
    return values[static_cast<std::size_t>(q)];
  }
  EngineeringValue& operator[](EngineeringQuantity q) noexcept {
    return values[static_cast<std::size_t>(q)];
  }
  // A table: one line per quantity, "label  value ± u_c unit", the fit's part and the largest
  // component when the rest adds more than 10 %, notes after.
  std::string Report() const;
  // Every quantity's budget, component by component, and the limitations.
  std::string BudgetReport() const;
};

// From an estimate (δ, ξ, which were estimated, and the covariance) and f0 (Hz; NaN if unknown).
// An unusable summary gives values from whatever δ, ξ hold, none determined.
EngineeringQuantities ComputeEngineeringQuantities(const EstimateSummary& summary,
                                                   double frequency_hz,
                                                   const EngineeringOptions& options = {});

// The values alone (no std, no significance), from a full parameter set in the model's frame:
// the exact maps, for tests and for the budget. Angles on the shell in degrees, as above.
std::array<double, kEngineeringQuantityCount> EngineeringValues(
    const Delta& delta, const Xi& xi, const EngineeringModel& model) noexcept;
// With only f0: no drift correction, the nominal pick-off.
std::array<double, kEngineeringQuantityCount> EngineeringValues(const Delta& delta, const Xi& xi,
                                                                double frequency_hz) noexcept;

// ω̇/ω0 from the runs' fitted common phases (FitDiagnostics: 2·q2 per run), weighted by the
// runs' samples, and the spread of the runs' values (sample std; NaN with fewer than two runs).
// NaN when no run has a fitted drift or f0 is unknown.
struct FrequencyDrift {
  double relative_rate_per_s = kNaN;
  double spread_per_s = kNaN;
  int runs = 0;
};
FrequencyDrift FittedFrequencyDrift(const FitDiagnostics& diagnostics,
                                    double frequency_hz) noexcept;

}  // namespace hrgbench::estimator
