#pragma once
// What a station declares of its pick-off ([gyro] pickoff_cross_talk_stage and
// pickoff_coupling_bound_rad in the station file, recorded as session.json electronics.pickoff):
// the two things about the pick-off that free runs cannot measure and the engineering quantities'
// budget carries (estimator/pickoff_frame.hpp, docs/estimator/physics-accuracy.md). Data only.

#include "hrgbench/estimator/pickoff_frame.hpp"

namespace hrgbench::bench {

struct PickoffDeclaration {
  // Where the channels' cross-talk sits, when the electronics' design says (kMidway: not known;
  // the budget then carries the distance to either end).
  estimator::CrossTalkStage cross_talk_stage = estimator::CrossTalkStage::kMidway;
  // A bound on an antisymmetric coupling of the pick-off beyond the model, rad (electrical frame
  // angle, both parts); 0: none declared (the budget names the component, not evaluated).
  double unmodelled_coupling_bound_rad = 0.0;
};
inline constexpr double kMaxCouplingBoundRad = 0.1;

}  // namespace hrgbench::bench
