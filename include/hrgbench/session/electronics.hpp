#pragma once
// What a station declares about its gyro's electronics, and the session record keeps under
// "electronics": the output low-pass filter ([gyro] output_filter, output_filter_order,
// output_filter_cutoff_hz) and the two things about the pick-off that free runs cannot measure
// ([gyro] pickoff_cross_talk_stage, pickoff_coupling_bound_rad). Plain data, in the session layer
// because three layers share it: the config layer reads it, the recorder writes it, the analysis
// makes the noise shape and the budget of it (analysis/output_filter.hpp,
// analysis/engineering_of_record.hpp; docs/estimator/physics-accuracy.md).

#include <cstdint>

#include "hrgbench/estimator/pickoff_frame.hpp"

namespace hrgbench::bench {

enum class OutputFilterKind {
  kNone,         // the electronics pass white pick-off noise (or filter far above the output rate)
  kButterworth,  // a Butterworth low-pass of `order` with cutoff `cutoff_hz`, then decimation
};

struct OutputFilter {
  OutputFilterKind kind = OutputFilterKind::kNone;
  std::int64_t order = 4;    // 1 … estimator::kMaxButterworthOrder
  double cutoff_hz = 200.0;  // > 0
};

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
