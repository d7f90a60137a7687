#include "sim/carrier_simulation.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "hrgbench/estimator/pickoff_frame.hpp"

namespace hrgbench::drivers::sim {

CarrierSimulation::CarrierSimulation(const CarrierOptions& options)
    : options_(options), pickoff_(options.pickoff, options.resonator.frequency_hz) {
  Release({});
}

double CarrierSimulation::FrequencyScale(double t_s) const noexcept {
  const double temperature = release_.temperature_c + release_.temperature_rate_c_per_s * t_s;
  return 1.0 + options_.frequency_temperature_coefficient_per_c *
                   (temperature - options_.reference_temperature_c);
}

void CarrierSimulation::Release(const CarrierRelease& release) noexcept {
  release_ = release;
  decimation_ =
      std::max(1, static_cast<int>(std::lround(options_.sample_rate_hz / release.output_rate_hz)));
  const double rate_hz = decimation_ * release.output_rate_hz;
  if (!resonator_ || resonator_->step_s() != 1.0 / rate_hz) {
    resonator_.emplace(options_.resonator, 1.0 / rate_hz);
  }
  electronics_.emplace(options_.electronics, rate_hz, decimation_);
  resonator_->SetConditions(release.omega_rad_s, FrequencyScale(0.0));
  pickoff_.Configure(*resonator_);
  pickoff_.Reset(release.seed);
  resonator_->Release(release.orbit);
  const double wave_rad_s = resonator_->mean_frequency_rad_s();
  electronics_->Release(wave_rad_s / (2.0 * std::numbers::pi),
                        pickoff_.HeldObservation(estimator::OrbitToState(release.orbit), wave_rad_s,
                                                 resonator_->velocity_scale_rad_s()));
  k_ = 0;
  ramp_start_valid_ = false;
}

estimator::Observation CarrierSimulation::Next(double omega_rad_s) noexcept {
  estimator::Observation y = estimator::Observation::Zero();
  const bool ramp = release_.temperature_rate_c_per_s != 0.0 &&
                    options_.frequency_temperature_coefficient_per_c != 0.0;
  if (!ramp) {
    const double t_mid = (static_cast<double>(k_) + 0.5) / release_.output_rate_hz;
    if (resonator_->SetConditions(omega_rad_s, FrequencyScale(t_mid))) {
      pickoff_.Configure(*resonator_);
    }
    for (int n = 0; n < decimation_; ++n) {
      electronics_->Push(pickoff_.Sample(resonator_->state()), &y);
      resonator_->Step();
    }
    ++k_;
    return y;
  }
  // The transitions at the period's start (the last period's end) and end, interpolated at each
  // converter step's mid-point: the stiffness moves every converter sample, evenly over the carrier
  // phase. (The pick-off's delays are taken at the period's end: they move by α·Ṫ·τ, ≪ 1e-9.)
  const double t_start = static_cast<double>(k_) / release_.output_rate_hz;
  const double t_end = static_cast<double>(k_ + 1) / release_.output_rate_hz;
  if (!ramp_start_valid_ || k_ == 0) {
    resonator_->SetConditions(omega_rad_s, FrequencyScale(t_start));
    ramp_start_transition_ = resonator_->transition();
  } else if (resonator_->SetConditions(omega_rad_s, FrequencyScale(t_start))) {
    ramp_start_transition_ = resonator_->transition();  // Ω changed: recompute the start too
  }
  resonator_->SetConditions(omega_rad_s, FrequencyScale(t_end));
  pickoff_.Configure(*resonator_);
  const Eigen::Matrix4d difference = resonator_->transition() - ramp_start_transition_;
  for (int n = 0; n < decimation_; ++n) {
    electronics_->Push(pickoff_.Sample(resonator_->state()), &y);
    resonator_->StepWith(ramp_start_transition_ + ((n + 0.5) / decimation_) * difference);
  }
  ramp_start_transition_ = resonator_->transition();
  ramp_start_valid_ = true;
  ++k_;
  return y;
}

namespace {

std::complex<double> Pair(const Eigen::Vector4d& u, int c) noexcept {
  return {u[2 * c], u[2 * c + 1]};
}

}  // namespace

void CarrierSimulation::SetControl(const Eigen::Matrix2cd& forcer_gain,
                                   const Eigen::Matrix2cd& feed_through) {
  forcer_gain_ = forcer_gain;
  feed_through_ = feed_through;
  resonator_->EnableDrive();
}

estimator::Observation CarrierSimulation::Observe(double omega_rad_s,
                                                  const Eigen::Vector4d& u_held) noexcept {
  const double t_mid = (static_cast<double>(k_) + 0.5) / release_.output_rate_hz;
  if (resonator_->SetConditions(omega_rad_s, FrequencyScale(t_mid))) {
    pickoff_.Configure(*resonator_);
  }
  const Eigen::Vector2cd fed = feed_through_ * Eigen::Vector2cd(Pair(u_held, 0), Pair(u_held, 1));
  observed_phasor_ = electronics_->reference().current();
  const std::complex<double> carrier = std::conj(observed_phasor_);  // e^{iψ}
  Eigen::Vector2d s = pickoff_.Sample(resonator_->state());
  s[0] += (fed[0] * carrier).real();
  s[1] += (fed[1] * carrier).real();
  estimator::Observation y = estimator::Observation::Zero();
  electronics_->Push(s, &y);  // the period's first converter sample is the output sample
  return y;
}

void CarrierSimulation::Advance(const Eigen::Vector4d& u) noexcept {
  const Eigen::Vector2cd command(Pair(u, 0), Pair(u, 1));
  const double w = resonator_->mean_frequency_rad_s();
  // P/ω0 (the resonator's force input is f/ω0) and the feed-through, for this period.
  const Eigen::Vector2cd drive =
      (-2.0 * w / resonator_->velocity_scale_rad_s() * DriveTrim()) * (forcer_gain_ * command);
  const Eigen::Vector2cd fed = feed_through_ * command;
  const std::complex<double> half_step = std::polar(1.0, 0.5 * w * resonator_->step_s());
  estimator::Observation unused = estimator::Observation::Zero();
  std::complex<double> phasor = observed_phasor_;
  for (int n = 0; n < decimation_; ++n) {
    if (n > 0) {
      phasor = electronics_->reference().current();
      const std::complex<double> carrier = std::conj(phasor);
      Eigen::Vector2d s = pickoff_.Sample(resonator_->state());
      s[0] += (fed[0] * carrier).real();
      s[1] += (fed[1] * carrier).real();
      electronics_->Push(s, &unused);
    }
    const std::complex<double> mid = std::conj(phasor) * half_step;  // e^{iψ} at the step's middle
    resonator_->StepDriven(Eigen::Vector2d((drive[0] * mid).real(), (drive[1] * mid).real()));
  }
  ++k_;
}

estimator::Delta CarrierSimulation::delta() const noexcept {
  // A temperature ramp moves the frequency, and the displacement's amplitude with it
  // (estimator/frequency_drift_decay.hpp): ω̇/ω = α·Ṫ/(1 + α·(T − T0)) at release.
  const double alpha = options_.frequency_temperature_coefficient_per_c;
  return estimator::SlowModelSeenOnUnit(
             options_.resonator, pickoff_.carrier_gain(),
             alpha * release_.temperature_rate_c_per_s / FrequencyScale(0.0))
      .delta;
}

estimator::Xi CarrierSimulation::xi() const noexcept {
  return estimator::SlowModelSeenOnUnit(options_.resonator, pickoff_.carrier_gain()).xi;
}

double CarrierSimulation::group_delay_s() const noexcept { return electronics_->group_delay_s(); }

}  // namespace hrgbench::drivers::sim
