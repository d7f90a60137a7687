#include "sim/carrier_pickoff.hpp"

#include <cmath>
#include <numbers>

namespace hrgbench::drivers::sim {

using Complex = std::complex<double>;

bool CarrierPickoffOptions::IsValid(std::string* why) const {
  const auto fail = [why](const char* message) {
    if (why != nullptr) *why = message;
    return false;
  };
  std::string part;
  if (!errors.IsValid(&part)) {
    if (why != nullptr) *why = "pick-off errors: " + part;
    return false;
  }
  if (!(std::isfinite(common_gain) && common_gain > 0.0)) {
    return fail("common_gain must be finite and > 0");
  }
  if (!(std::isfinite(common_delay_s) && common_delay_s >= 0.0)) {
    return fail("common_delay_s must be finite and >= 0");
  }
  if (!(std::isfinite(white_noise_std) && white_noise_std >= 0.0) ||
      !(std::isfinite(coloured_noise_std) && coloured_noise_std >= 0.0)) {
    return fail("white_noise_std and coloured_noise_std must be finite and >= 0");
  }
  if (!(std::isfinite(coloured_noise_time_s) && coloured_noise_time_s > 0.0)) {
    return fail("coloured_noise_time_s must be finite and > 0");
  }
  return true;
}

CarrierPickoff::CarrierPickoff(const CarrierPickoffOptions& options, double design_frequency_hz)
    : options_(options), design_rad_s_(2.0 * std::numbers::pi * design_frequency_hz) {
  const estimator::PickoffParameters& e = options.errors;
  // Row c: what electrode c reads of (q1, q2): cos β, sin β at β = 0 and 90° − ε.
  Eigen::Matrix2cd electrodes;
  electrodes << 1.0, 0.0, std::sin(e.electrode_angle_error_rad),
      std::cos(e.electrode_angle_error_rad);
  // Each electrode line's pick-up of the other, 90° late at the carrier: e^{−iπ/2}.
  const auto coupling = [](double kappa) {
    const Complex late = std::polar(kappa, -0.5 * std::numbers::pi);
    Eigen::Matrix2cd k;
    k << 1.0, late, late, 1.0;
    return k;
  };
  Eigen::Matrix2cd chains = Eigen::Matrix2cd::Zero();
  chains(0, 0) = std::polar(options.common_gain, -design_rad_s_ * options.common_delay_s);
  chains(1, 1) = chains(0, 0) * std::polar(e.gain_ratio, -e.phase_mismatch_rad);
  switch (options.cross_talk_stage) {
    case estimator::CrossTalkStage::kBeforeGain:
      gain_ = chains * coupling(e.cross_talk) * electrodes;
      break;
    case estimator::CrossTalkStage::kAfterGain:
      gain_ = coupling(e.cross_talk) * chains * electrodes;
      break;
    case estimator::CrossTalkStage::kMidway:
      gain_ = coupling(0.5 * e.cross_talk) * chains * coupling(0.5 * e.cross_talk) * electrodes;
      break;
  }
  model_frame_ = estimator::DecomposePickoffGain(gain_);
  const Complex c = std::cos(model_frame_.frame_angle), s = std::sin(model_frame_.frame_angle);
  model_from_electrode_ << c, -s, s, c;
  model_from_electrode_ *= model_frame_.common;
  Reset(1);
}

estimator::State CarrierPickoff::ModelState(const estimator::State& x) const noexcept {
  const Eigen::Vector2cd u(Complex(x[0], x[1]), Complex(x[2], x[3]));
  const Eigen::Vector2cd v = model_from_electrode_ * u;
  return {v[0].real(), v[0].imag(), v[1].real(), v[1].imag()};
}

void CarrierPickoff::Configure(const CarrierResonator& resonator) noexcept {
  output_.setZero();
  for (int c = 0; c < 2; ++c) {
    for (int j = 0; j < 2; ++j) {
      const std::complex<double> h = gain_(c, j);
      const double magnitude = std::abs(h);
      if (magnitude == 0.0) continue;
      const double delay_s = -std::arg(h) / design_rad_s_;
      // q_j(t − τ) = row j of exp(−F·τ)·X(t).
      if (delay_s == 0.0) {
        output_(c, j) += magnitude;
      } else {
        output_.row(c) += magnitude * resonator.Transition(-delay_s).row(j);
      }
    }
  }
  rho_ = std::exp(-resonator.step_s() / options_.coloured_noise_time_s);
  drive_ = std::sqrt(1.0 - rho_ * rho_) * options_.coloured_noise_std;
}

void CarrierPickoff::Reset(std::uint64_t seed) noexcept {
  white_.emplace(seed);
  coloured_noise_.emplace(seed + kColouredStream);
  for (double& n : coloured_) n = options_.coloured_noise_std * coloured_noise_->Next();
}

estimator::Observation CarrierPickoff::HeldObservation(const estimator::State& x,
                                                       double frequency_rad_s,
                                                       double velocity_scale_rad_s) const noexcept {
  // A steady tone X(t) = (Re[u·e^{iωt}], Re[iω·u·e^{iωt}]/ω0) gives s_c = Re[(P_q + i(ω/ω0)·P_v)·u·
  // e^{iωt}], which demodulates (2·LPF[s·e^{−iωt}]) to (P_q + i(ω/ω0)·P_v)·u.
  const std::complex<double> u[2] = {{x[0], x[1]}, {x[2], x[3]}};
  const double v = frequency_rad_s / velocity_scale_rad_s;
  estimator::Observation y;
  for (int c = 0; c < 2; ++c) {
    std::complex<double> w = 0.0;
    for (int j = 0; j < 2; ++j) {
      w += std::complex<double>(output_(c, j), v * output_(c, 2 + j)) * u[j];
    }
    y[2 * c] = w.real();
    y[2 * c + 1] = w.imag();
  }
  return y;
}

}  // namespace hrgbench::drivers::sim
