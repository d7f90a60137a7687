#pragma once
// SlowModelSource: physics = "slow". y = (I + C(ξ))·x(t) + σ·n with x(t) from the exact closed-form
// propagation of the model (estimator::PropagateExact from OrbitToState(a, b, θ, φ = 0) at
// release), independent N(0, σ²) per channel from NormalGenerator(seed + run). Ω is read at every
// sample; when it changes the state is re-anchored (exact for piecewise-constant Ω).
// The estimator fits exactly this model: use it to test the bench, not the estimator's realism.

#include <optional>

#include "hrgbench/estimator/simulation.hpp"
#include "sim/free_run_source.hpp"

namespace hrgbench::drivers::sim {

class SlowModelSource final : public FreeRunSource {
 public:
  SlowModelSource(const estimator::Delta& delta, const estimator::Xi& xi, double sigma,
                  std::uint64_t seed, double resonant_frequency_hz);

  void Release(const FreeRunStart& start) noexcept override;
  estimator::Observation Sample(std::uint64_t k, std::int64_t t_ns,
                                double omega_rad_s) noexcept override;
  double ReportedFrequencyHz(double temperature_c) const noexcept override;

 private:
  estimator::Delta delta_;
  estimator::Matrix4 distortion_;  // I + C(ξ)
  double sigma_;
  std::uint64_t seed_;
  double resonant_frequency_hz_;
  estimator::State anchor_x_ = estimator::State::Zero();
  std::int64_t anchor_ns_ = 0;
  double anchor_omega_ = 0.0;
  std::optional<estimator::NormalGenerator> noise_;
};

}  // namespace hrgbench::drivers::sim
