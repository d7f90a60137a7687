#include "sim/carrier_electronics.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <iterator>

#include "gyro_can/gyro_codec.hpp"

namespace hrgbench::drivers::sim {

bool CarrierElectronicsOptions::IsValid(std::string* why) const {
  if (!reference.IsValid(why)) return false;
  if (filter_order < 2 || filter_order > ButterworthLowPass::kMaxOrder || filter_order % 2 != 0) {
    if (why != nullptr) *why = "filter_order must be even, 2 to 8";
    return false;
  }
  if (!(std::isfinite(filter_cutoff_hz) && filter_cutoff_hz > 0.0)) {
    if (why != nullptr) *why = "filter_cutoff_hz must be finite and > 0";
    return false;
  }
  return true;
}

CarrierElectronics::CarrierElectronics(const CarrierElectronicsOptions& options,
                                       double sample_rate_hz, int decimation)
    : options_(options),
      output_period_s_(decimation / sample_rate_hz),
      decimation_(decimation),
      reference_(options.reference, sample_rate_hz),
      filter_(options.filter_order, options.filter_cutoff_hz, sample_rate_hz) {
  const double delay_periods =
      std::min(filter_.group_delay_s() / output_period_s_, kPhaseHistory - 1.0);
  delay_whole_ = static_cast<int>(std::floor(delay_periods));
  delay_fraction_ = delay_periods - delay_whole_;
}

void CarrierElectronics::Release(double wave_frequency_hz,
                                 const estimator::Observation& held) noexcept {
  reference_.Lock(wave_frequency_hz);
  filter_.SetSteadyState(held.array());
  phase_ = 0;
  std::fill(std::begin(history_), std::end(history_), 0.0);  // locked before release: χ = 0
  history_head_ = 0;
  reported_phase_rad_ = 0.0;
}

bool CarrierElectronics::Push(const Eigen::Vector2d& s, estimator::Observation* y) noexcept {
  const double chi_rad = reference_.phase_rad();     // χ of this converter sample
  const std::complex<double> r = reference_.Next();  // e^{−iψ}
  const double c2 = 2.0 * r.real(), s2 = 2.0 * r.imag();
  const Eigen::Array4d mixed(s[0] * c2, s[0] * s2, s[1] * c2, s[1] * s2);
  const Eigen::Array4d filtered = filter_.Filter(mixed);
  if (phase_++ != 0) {
    if (phase_ == decimation_) phase_ = 0;
    return false;
  }
  if (decimation_ == 1) phase_ = 0;
  // χ(t − τg): interpolated between the output samples delay_whole_ and delay_whole_ + 1 back.
  history_head_ = (history_head_ + 1) % kPhaseHistory;
  history_[history_head_] = chi_rad;
  const double newer = history_[(history_head_ - delay_whole_ + kPhaseHistory) % kPhaseHistory];
  const double older = history_[(history_head_ - delay_whole_ - 1 + kPhaseHistory) % kPhaseHistory];
  reported_phase_rad_ = newer + delay_fraction_ * (older - newer);
  if (options_.reference.mode == ReferenceMode::kTracking) {
    // The orbit's phase: u1² + u2² = e^{2iφ}·(a² − b²).
    const std::complex<double> u1(filtered[0], filtered[1]), u2(filtered[2], filtered[3]);
    reference_.Correct(0.5 * std::arg(u1 * u1 + u2 * u2), output_period_s_);
  }
  // The chain computes in the model's convention; plus-sine electronics output its conjugate.
  Eigen::Array4d out = filtered;
  if (options_.iq_convention == estimator::IqConvention::kPlusSine) {
    out[1] = -out[1];
    out[3] = -out[3];
    reported_phase_rad_ = -reported_phase_rad_;
  }
  for (int c = 0; c < 4; ++c) {
    (*y)[c] = options_.quantise ? gyro_can::DequantiseY(gyro_can::QuantiseY(out[c])) : out[c];
  }
  return true;
}

}  // namespace hrgbench::drivers::sim
