#include "sim/reference_oscillator.hpp"

#include <cmath>
#include <numbers>

namespace hrgbench::drivers::sim {
namespace {
constexpr double kTwoPi = 2.0 * std::numbers::pi;
}  // namespace

bool ReferenceOptions::IsValid(std::string* why) const {
  if (!std::isfinite(offset_hz) || std::abs(offset_hz) > 100.0) {
    if (why != nullptr) *why = "reference offset_hz must be finite and within +-100 Hz";
    return false;
  }
  if (!(std::isfinite(pll_bandwidth_hz) && pll_bandwidth_hz > 0.0 && pll_bandwidth_hz <= 100.0)) {
    if (why != nullptr) *why = "pll_bandwidth_hz must be in (0, 100]";
    return false;
  }
  return true;
}

ReferenceOscillator::ReferenceOscillator(const ReferenceOptions& options, double sample_rate_hz)
    : options_(options), sample_rate_hz_(sample_rate_hz) {}

void ReferenceOscillator::Lock(double wave_frequency_hz) noexcept {
  lock_rad_s_ = kTwoPi * wave_frequency_hz;
  integral_rad_s_ = 0.0;
  correction_ = 0.0;
  block_phase_ = 0.0;
  count_ = 0;
  const double offset =
      options_.mode == ReferenceMode::kFreeRunning ? kTwoPi * options_.offset_hz : 0.0;
  SetIncrement(lock_rad_s_ + offset);
  phasor_ = {1.0, 0.0};
}

void ReferenceOscillator::SetIncrement(double frequency_rad_s) noexcept {
  current_rad_s_ = frequency_rad_s;
  increment_ = frequency_rad_s / sample_rate_hz_;
  rotation_ = std::polar(1.0, -increment_);
}

void ReferenceOscillator::Resync() noexcept {
  block_phase_ = std::fmod(block_phase_ + count_ * increment_, kTwoPi);
  correction_ += count_ * (increment_ - lock_rad_s_ / sample_rate_hz_);
  count_ = 0;
  phasor_ = std::polar(1.0, -block_phase_);
}

void ReferenceOscillator::Correct(double phase_error_rad, double period_s) noexcept {
  if (options_.mode != ReferenceMode::kTracking) return;
  const double wn = kTwoPi * options_.pll_bandwidth_hz;
  integral_rad_s_ += wn * wn * phase_error_rad * period_s;
  Resync();  // the phase so far at the old frequency
  SetIncrement(lock_rad_s_ + integral_rad_s_ + std::sqrt(2.0) * wn * phase_error_rad);
}

double ReferenceOscillator::frequency_hz() const noexcept { return current_rad_s_ / kTwoPi; }

double ReferenceOscillator::phase_rad() const noexcept {
  return correction_ + count_ * (increment_ - lock_rad_s_ / sample_rate_hz_);
}

}  // namespace hrgbench::drivers::sim
