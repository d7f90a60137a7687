#include "sim/slow_model_source.hpp"

namespace hrgbench::drivers::sim {

SlowModelSource::SlowModelSource(const estimator::Delta& delta, const estimator::Xi& xi,
                                 double sigma, std::uint64_t seed, double resonant_frequency_hz)
    : delta_(delta),
      distortion_(estimator::Matrix4::Identity() + estimator::DistortionMatrix(xi)),
      sigma_(sigma),
      seed_(seed),
      resonant_frequency_hz_(resonant_frequency_hz) {}

void SlowModelSource::Release(const FreeRunStart& start) noexcept {
  anchor_x_ = estimator::OrbitToState(start.orbit);
  anchor_ns_ = 0;
  anchor_omega_ = start.omega_rad_s;
  noise_.emplace(seed_ + start.run_index);
}

estimator::Observation SlowModelSource::Sample(std::uint64_t /*k*/, std::int64_t t_ns,
                                               double omega_rad_s) noexcept {
  if (omega_rad_s != anchor_omega_) {
    // Ω changed: carry the state to now under the old Ω, continue from here under the new one.
    anchor_x_ = estimator::PropagateExact(anchor_omega_, delta_, anchor_x_,
                                          static_cast<double>(t_ns - anchor_ns_) * 1e-9);
    anchor_ns_ = t_ns;
    anchor_omega_ = omega_rad_s;
  }
  const estimator::State x = estimator::PropagateExact(
      anchor_omega_, delta_, anchor_x_, static_cast<double>(t_ns - anchor_ns_) * 1e-9);
  estimator::Observation y = distortion_ * x;
  for (int c = 0; c < 4; ++c) {
    if (sigma_ > 0) y(c) += sigma_ * noise_->Next();
  }
  return y;
}

double SlowModelSource::ReportedFrequencyHz(double /*temperature_c*/) const noexcept {
  return resonant_frequency_hz_;
}

}  // namespace hrgbench::drivers::sim
