#pragma once
// CarrierPickoff: the two pick-off channels at the carrier (electrodes at 0 and 45° on the shell,
// 0 and 90° in the frame of q), with the channel gains and delays, cross-talk and electrode angle
// errors of estimator::PickoffParameters, and the converters' noise.
//
// The four errors are realised as the physical pick-off they name (estimator/pickoff_frame.hpp's
// nominal model, written out here from the electrodes, not through the estimator's maps): channel
// 1's electrode at 0, channel 2's at 90° − ε in the frame of q (each reads q1·cosβ + q2·sinβ),
// each electrode line picking up κ times the other's signal 90° late, channel 2's chain the gain
// g and the extra delay Δφ/ω_d, and both the common gain and delay; the cross-talk enters before
// the gains or, with cross_talk_stage = kAfterGain, after them. The resulting complex gain H from
// q_j to channel c at the design frequency is the unit's; what the slow model sees of it is
// estimator::DecomposePickoffGain(H) (ξ and the frame angle it cannot hold). Each of the four paths
// is a gain |H_cj| and a true time delay τ_cj = −arg(H_cj)/ω_d (principal value: a path whose
// phase leads is a small advance, which the linear oscillator also gives exactly), applied as
// q_j(t − τ) = rows of exp(−F·τ)·X(t): so the phase is exact at the design frequency and a delay
// at any other (f(T) ≠ f0, the modes at f0 ± Δf/2), as in a real chain.
//
// Noise per channel and converter sample (same unit as q): white, std white_noise_std, and AR(1)
// coloured, std coloured_noise_std with correlation time coloured_noise_time_s
// (n_k = ρ·n_{k−1} + √(1 − ρ²)·σ_c·e_k, ρ = e^{−dt/τ_c}, started stationary). Seeded: white from
// NormalGenerator(seed), coloured from NormalGenerator(seed + kColouredStream).
//
// Threads: one thread. Real-time: Sample() is allocation-free and noexcept; Configure() computes
// up to four 4×4 matrix exponentials.

#include <cstdint>
#include <optional>
#include <string>

#include "hrgbench/estimator/physical_parameters.hpp"
#include "hrgbench/estimator/pickoff_frame.hpp"
#include "hrgbench/estimator/simulation.hpp"
#include "sim/carrier_resonator.hpp"

namespace hrgbench::drivers::sim {

struct CarrierPickoffOptions {
  estimator::PickoffParameters errors;  // channel 2 relative to channel 1 (→ ξ)
  double common_gain = 1.0;             // both channels' mean gain (absorbed by x0), > 0
  double common_delay_s = 0.0;          // both channels' mean delay (absorbed by x0), ≥ 0
  double white_noise_std = 0.0;         // per channel and converter sample, unit of q
  double coloured_noise_std = 0.0;      // AR(1) part, stationary std, unit of q
  double coloured_noise_time_s = 1e-3;  // its correlation time, > 0
  // Where the cross-talk enters: at the electrode lines (before the gains) or between the
  // amplified channels.
  estimator::CrossTalkStage cross_talk_stage = estimator::CrossTalkStage::kBeforeGain;

  bool IsValid(std::string* why) const;
};

class CarrierPickoff {
 public:
  static constexpr std::uint64_t kColouredStream = 0x9E3779B97F4A7C15ull;

  // `design_frequency_hz`: where the path phases are exact (the resonator's f0).
  CarrierPickoff(const CarrierPickoffOptions& options, double design_frequency_hz);

  // Rebuilds the output matrix for the resonator's current conditions (call after SetConditions
  // changed them) and its time step (the coloured noise's ρ).
  void Configure(const CarrierResonator& resonator) noexcept;
  void Reset(std::uint64_t seed) noexcept;  // the noise generators, per run

  // Both channels' converter samples for the oscillator's state now.
  Eigen::Vector2d Sample(const CarrierState& state) noexcept {
    Eigen::Vector2d s = output_ * state;
    if (options_.white_noise_std > 0.0) {
      s[0] += options_.white_noise_std * white_->Next();
      s[1] += options_.white_noise_std * white_->Next();
    }
    if (options_.coloured_noise_std > 0.0) {
      for (int c = 0; c < 2; ++c) {
        coloured_[c] = rho_ * coloured_[c] + drive_ * coloured_noise_->Next();
        s[c] += coloured_[c];
      }
    }
    return s;
  }

  // The demodulated value (x-order) of a steady tone at `frequency_rad_s` carrying the slow state
  // x: what the channels show for a wave held at x (before release).
  estimator::Observation HeldObservation(const estimator::State& x, double frequency_rad_s,
                                         double velocity_scale_rad_s) const noexcept;
  // H at the design frequency (common gain and delay included), and what the slow model holds of
  // it: ξ in its frame, and the frame angle it cannot hold (estimator/pickoff_frame.hpp).
  const Eigen::Matrix2cd& carrier_gain() const noexcept { return gain_; }
  const estimator::Xi& xi() const noexcept { return model_frame_.xi; }
  std::complex<double> frame_angle() const noexcept { return model_frame_.frame_angle; }
  std::complex<double> common() const noexcept { return model_frame_.common; }  // c
  // The slow model's state of a wave whose slow variables in the electrode frame are `x`:
  // c·V(a)·u, so that the channels read (I + C(ξ))·ModelState(x).
  estimator::State ModelState(const estimator::State& x) const noexcept;
  // c·V(a) itself: the complex 2×2 from the electrode frame's slow variables to the model's.
  const Eigen::Matrix2cd& model_from_electrode() const noexcept { return model_from_electrode_; }

 private:
  CarrierPickoffOptions options_;
  double design_rad_s_;
  Eigen::Matrix2cd gain_;
  estimator::PickoffInModelFrame model_frame_;
  Eigen::Matrix2cd model_from_electrode_ = Eigen::Matrix2cd::Identity();
  Eigen::Matrix<double, 2, 4> output_ = Eigen::Matrix<double, 2, 4>::Zero();
  std::optional<estimator::NormalGenerator> white_;
  std::optional<estimator::NormalGenerator> coloured_noise_;
  double coloured_[2] = {0.0, 0.0};
  double rho_ = 0.0;
  double drive_ = 0.0;
};

}  // namespace hrgbench::drivers::sim
