#pragma once
// The physical pick-off, and the frame the slow model's fit is in.
//
// ## The physical pick-off (the nominal model)
// Channel 1's electrode defines the frame: q1 is the n = 2 mode's displacement under it, q2 under
// a point 45° further on the shell (90° in the electrical frame of q, physical_parameters.hpp).
// An electrode at electrical angle β sees q1·cosβ + q2·sinβ. Channel 2's electrode sits at
// β2 = 90° − ε (the electrodes are 45° − ε/2 apart on the shell). Each electrode line picks up
// κ times the other's signal 90° late (a capacitive coupling: −i at the carrier), and channel 2's
// chain has the complex gain ρ = g·e^{−iΔφ} relative to channel 1's. On the slow variables
// u = (u1, u2) of the electrode frame the channels are w = h·H·u, h channel 1's own complex gain,
//
//     H = G·K(κ)·P           (cross-talk at the electrode lines, before the gains: kBeforeGain)
//     H = K(κ)·G·P           (cross-talk between the amplified channels: kAfterGain)
//     H = K(κ/2)·G·K(κ/2)·P  (half of each: kMidway, the nominal model when nobody knows)
//
//     G = | 1  0 |   K(κ) = | 1    −iκ |   P = | 1     0    |
//         | 0  ρ |          | −iκ   1  |       | sin ε cos ε |
//
// The two orders differ at second order (K·G − G·K = iκ·(ρ − 1)·J, antisymmetric): the physics
// of the pick-off does not fix where a coupling sits, so the engineering quantities take the
// middle (kMidway) and carry the distance to either end as a systematic uncertainty.
//
// ## What the model can hold
// model.md's y = (I + C(ξ))·x holds a common complex factor c and the symmetric form
// I + C(ξ) = [[1 + p, q], [q, 1 − p]] (p = ξ1 − iξ2, q = ξ4 − iξ3): 6 of the 8 real numbers of a
// complex 2×2. Every invertible H is, uniquely near the identity,
//
//     H = c·(I + C(ξ))·V(a),   V(a) = cos a·I + sin a·J = exp(a·J),   J = | 0 −1 |,
//                                                                        | 1  0 |
//
// with a complex frame angle a: tan a = (H21 − H12)/(H11 + H22). V commutes with I and with the
// Coriolis term's σy, so data of a unit whose pick-off is H and whose anisotropies are D_c·σz +
// D_s·σx (D_c = δ3 + iδ5, D_s = δ4 + iδ6, in the electrode frame) are exactly data of the model
// with ξ and the anisotropies turned by the complex angle 2a:
//
//     (D_c, D_s)_model = R(2a)·(D_c, D_s)_electrode,   R(φ) = | cos φ  −sin φ |
//                                                              | sin φ   cos φ |
//
// Free runs cannot tell a from the anisotropies' own angles. Its real part turns both axes (the
// model's frame sits a from channel 1's electrode: ε/2 for a misplaced electrode, i.e. ε/4 on
// the shell); its imaginary part η = Im a mixes the frequency split into the damping split,
// (δ3, δ4) gaining ≈ 2η·(δ6, −δ5) (and (δ5, δ6) 2η·(−δ4, δ3)): at a 50 mHz split, η = 1e-4
// moves Δ(1/τ) by 6e-5 1/s. Only a model of the pick-off fixes a: given ξ, the physical errors
// (g, Δφ, κ, ε) are the ones whose H has that ξ, and a is then H's.
//
// Pure functions, Eigen and the standard library only, noexcept, allocation-free.

#include <Eigen/Core>
#include <complex>

#include "hrgbench/estimator/parameters.hpp"
#include "hrgbench/estimator/physical_parameters.hpp"

namespace hrgbench::estimator {

// Where the channels' cross-talk enters (see above).
enum class CrossTalkStage {
  kMidway,      // half at the electrode lines, half between the amplified channels (nominal)
  kBeforeGain,  // at the electrode lines, before each channel's gain and delay
  kAfterGain,   // between the amplified channels
};
const char* ToString(CrossTalkStage stage) noexcept;

// H of the physical pick-off, relative to channel 1's own gain (H11 = 1 when κ = 0).
Eigen::Matrix2cd PhysicalPickoffGain(const PickoffParameters& pickoff,
                                     CrossTalkStage stage = CrossTalkStage::kMidway) noexcept;

// H = common·(I + C(xi))·V(frame_angle): what the model holds of a pick-off, and what it cannot.
struct PickoffInModelFrame {
  std::complex<double> common = 1.0;  // c, absorbed by each run's initial state
  Xi xi = Xi::Zero();                 // the model's ξ
  std::complex<double> frame_angle =
      0.0;  // a, rad (electrical): the model's frame from channel 1's
};
// Any H with H11 + H22 ≠ 0.
PickoffInModelFrame DecomposePickoffGain(const Eigen::Matrix2cd& gain) noexcept;

// The physical pick-off errors whose H, under `stage`, has the model's ξ = `xi`, and H's frame
// angle. Newton's method from the first-order map (a few iterations; converged = false when it
// did not reach 1e-13 in ξ, e.g. for |ξ| near 1, then the last iterate).
struct PhysicalPickoff {
  PickoffParameters pickoff;
  std::complex<double> frame_angle = 0.0;  // rad, electrical
  bool converged = false;
};
PhysicalPickoff PhysicalPickoffFromXi(const Xi& xi,
                                      CrossTalkStage stage = CrossTalkStage::kMidway) noexcept;

// The two directions as one call each, under the nominal model: the model's ξ of a physical
// pick-off, and the physical pick-off of a model's ξ.
Xi XiFromPickoff(const PickoffParameters& pickoff,
                 CrossTalkStage stage = CrossTalkStage::kMidway) noexcept;
PickoffParameters PickoffFromXi(const Xi& xi,
                                CrossTalkStage stage = CrossTalkStage::kMidway) noexcept;

// δ with its anisotropies turned from the model's frame into channel 1's electrode frame (R(−2a)),
// and back (R(+2a)). δ1 and δ2 are unchanged.
Delta DeltaInElectrodeFrame(const Delta& model_delta, std::complex<double> frame_angle) noexcept;
Delta DeltaInModelFrame(const Delta& electrode_delta, std::complex<double> frame_angle) noexcept;

// What an output-error fit of the slow model finds on a physical unit: δ in the model's frame
// (with the decay a frequency drift adds, frequency_drift_decay.hpp) and ξ in the model's frame
// with the split's second-order Coriolis mixing (split_coriolis_mixing.hpp). `pickoff_gain` is
// the unit's H (any common factor); `relative_frequency_rate_per_s` ω̇/ω during the run.
struct SlowModelTruth {
  Delta delta = Delta::Zero();
  Xi xi = Xi::Zero();
  std::complex<double> frame_angle = 0.0;
};
SlowModelTruth SlowModelSeenOnUnit(const ResonatorParameters& resonator,
                                   const Eigen::Matrix2cd& pickoff_gain,
                                   double relative_frequency_rate_per_s = 0.0) noexcept;

}  // namespace hrgbench::estimator
