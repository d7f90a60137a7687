#include "sim/table_physics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace hrgbench::drivers::sim {

using hw::RateTableFault;
using hw::RateTableMode;

bool TablePhysicsOptions::IsValid(std::string* why) const {
  const auto positive = [why](const char* name, double v) {
    if (std::isfinite(v) && v > 0.0) return true;
    if (why != nullptr) {
      std::ostringstream os;
      os << name << " must be finite and > 0, got " << v;
      *why = os.str();
    }
    return false;
  };
  return positive("max_rate_rad_s", max_rate_rad_s) &&
         positive("accel_limit_rad_s2", accel_limit_rad_s2) &&
         positive("max_accel_rad_s2", max_accel_rad_s2) &&
         positive("settle_time_constant_s", settle_time_constant_s) &&
         positive("stable_tolerance_rad_s", stable_tolerance_rad_s) &&
         positive("stable_hold_s", stable_hold_s) &&
         positive("motion_threshold_rad_s", motion_threshold_rad_s) &&
         positive("estop_decel_rad_s2", estop_decel_rad_s2) && positive("step_s", step_s) &&
         positive("watchdog_ms", watchdog_ms) &&
         (noise_rad_s >= 0.0 || positive("noise_rad_s", noise_rad_s)) &&
         positive("encoder_counts_per_rev", encoder_counts_per_rev) &&
         ((std::isfinite(encoder_noise_rad) && encoder_noise_rad >= 0.0) ||
          positive("encoder_noise_rad", encoder_noise_rad));
}

namespace {
std::mt19937_64 EncoderGenerator(std::uint64_t seed) {
  // Its own stream, so that angle reads do not shift the rate noise the status reads see.
  std::seed_seq sequence{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                         2u};
  return std::mt19937_64(sequence);
}
}  // namespace

TablePhysics::TablePhysics(TablePhysicsOptions options, const hw::Clock& clock)
    : options_(options),
      clock_(clock),
      accel_rad_s2_(options.accel_limit_rad_s2),
      watchdog_ms_(options.watchdog_ms),
      t_ns_(clock.NowNs()),
      last_heartbeat_ns_(t_ns_),
      rng_(options.seed),
      encoder_rng_(EncoderGenerator(options.seed)) {}

void TablePhysics::Trip(RateTableFault fault) {
  if (fault_code_ == 0) fault_code_ = static_cast<std::uint16_t>(fault);  // the first cause
  mode_ = RateTableMode::kIdle;
  target_rad_s_ = 0.0;
}

void TablePhysics::AdvanceTo(std::int64_t now_ns) {
  const auto step_ns = static_cast<std::int64_t>(options_.step_s * 1e9);
  const std::int64_t watchdog_ns = std::int64_t{watchdog_ms_} * 1'000'000;
  while (t_ns_ < now_ns) {
    const std::int64_t dt_ns = std::min(step_ns, now_ns - t_ns_);
    t_ns_ += dt_ns;
    const double dt_s = static_cast<double>(dt_ns) * 1e-9;
    if (mode_ == RateTableMode::kRate && t_ns_ - last_heartbeat_ns_ > watchdog_ns) {
      Trip(RateTableFault::kWatchdog);
    }
    const bool moving_allowed = mode_ == RateTableMode::kRate && fault_code_ == 0;
    const double goal = moving_allowed ? target_rad_s_ : 0.0;
    const double decel = estop_ ? options_.estop_decel_rad_s2 : accel_rad_s2_;
    const double max_step = decel * dt_s;
    ramp_rad_s_ += std::clamp(goal - ramp_rad_s_, -max_step, max_step);
    const double tau = options_.settle_time_constant_s;
    const double decay = 1.0 - std::exp(-dt_s / tau);
    // The angle is the integral of the same solution, w(t) = r + (w0 - r) exp(-t / tau), over the
    // step; so the mean rate from the angle is exactly the mean of the rate the gyro senses.
    angle_rad_ += ramp_rad_s_ * dt_s + (rate_rad_s_ - ramp_rad_s_) * tau * decay;
    rate_rad_s_ += (ramp_rad_s_ - rate_rad_s_) * decay;
    if (std::abs(rate_rad_s_) > 1.1 * options_.max_rate_rad_s) Trip(RateTableFault::kOverspeed);
    const bool at_rate = moving_allowed && ramp_rad_s_ == target_rad_s_ &&
                         std::abs(rate_rad_s_ - target_rad_s_) <= options_.stable_tolerance_rad_s;
    if (at_rate && !stable_window_open_) {
      stable_window_open_ = true;
      stable_since_ns_ = t_ns_;
    }
    if (!at_rate) stable_window_open_ = false;
    stable_ = stable_window_open_ &&
              static_cast<double>(t_ns_ - stable_since_ns_) * 1e-9 >= options_.stable_hold_s;
  }
}

bool TablePhysics::Command(RateTableMode mode, double rate_rad_s) {
  std::lock_guard lock(mutex_);
  AdvanceTo(clock_.NowNs());
  if (!std::isfinite(rate_rad_s) || std::abs(rate_rad_s) > options_.max_rate_rad_s) return false;
  if (mode == RateTableMode::kIdle) {
    mode_ = RateTableMode::kIdle;
    target_rad_s_ = 0.0;
    return true;
  }
  if (interlock_open_) {
    Trip(RateTableFault::kInterlock);
    return false;
  }
  if (fault_code_ != 0) return false;
  if (mode_ != RateTableMode::kRate) last_heartbeat_ns_ = t_ns_;
  mode_ = RateTableMode::kRate;
  target_rad_s_ = rate_rad_s;
  return true;
}

bool TablePhysics::SetAccelLimit(double accel_rad_s2) {
  std::lock_guard lock(mutex_);
  if (!std::isfinite(accel_rad_s2) || accel_rad_s2 <= 0.0 ||
      accel_rad_s2 > options_.max_accel_rad_s2) {
    return false;
  }
  AdvanceTo(clock_.NowNs());
  accel_rad_s2_ = accel_rad_s2;
  return true;
}

bool TablePhysics::SetWatchdogMs(std::uint16_t watchdog_ms) {
  std::lock_guard lock(mutex_);
  if (watchdog_ms < 100 || watchdog_ms > 60000) return false;
  AdvanceTo(clock_.NowNs());
  watchdog_ms_ = watchdog_ms;
  return true;
}

void TablePhysics::Heartbeat(std::uint16_t value) {
  std::lock_guard lock(mutex_);
  AdvanceTo(clock_.NowNs());
  heartbeat_echo_ = value;
  last_heartbeat_ns_ = t_ns_;
}

void TablePhysics::ResetFault() {
  std::lock_guard lock(mutex_);
  AdvanceTo(clock_.NowNs());
  fault_code_ = estop_ ? static_cast<std::uint16_t>(RateTableFault::kEStop) : 0;
}

void TablePhysics::SetEStop(bool pressed) {
  std::lock_guard lock(mutex_);
  AdvanceTo(clock_.NowNs());
  estop_ = pressed;
  if (pressed) Trip(RateTableFault::kEStop);
}

void TablePhysics::SetInterlockOpen(bool open) {
  std::lock_guard lock(mutex_);
  AdvanceTo(clock_.NowNs());
  interlock_open_ = open;
  if (open &&
      (mode_ == RateTableMode::kRate || std::abs(rate_rad_s_) > options_.motion_threshold_rad_s)) {
    Trip(RateTableFault::kInterlock);
  }
}

void TablePhysics::InjectFault(RateTableFault fault) {
  std::lock_guard lock(mutex_);
  AdvanceTo(clock_.NowNs());
  Trip(fault);
}

hw::RateTableStatus TablePhysics::Status() {
  std::lock_guard lock(mutex_);
  AdvanceTo(clock_.NowNs());
  hw::RateTableStatus s;
  s.t_ns = t_ns_;
  s.mode = mode_;
  s.commanded_rate_rad_s = mode_ == RateTableMode::kRate ? target_rad_s_ : 0.0;
  s.measured_rate_rad_s = rate_rad_s_ + options_.noise_rad_s * normal_(rng_);
  s.rate_stable = stable_;
  s.in_motion = std::abs(rate_rad_s_) > options_.motion_threshold_rad_s ||
                std::abs(ramp_rad_s_) > options_.motion_threshold_rad_s;
  s.fault = fault_code_ != 0;
  s.estop = estop_;
  s.interlock_open = interlock_open_;
  s.fault_code = fault_code_;
  s.temperature_c = options_.temperature_c;
  s.heartbeat_echo = heartbeat_echo_;
  return s;
}

double TablePhysics::TrueRateRadS() {
  std::lock_guard lock(mutex_);
  AdvanceTo(clock_.NowNs());
  return rate_rad_s_;
}

hw::RateTableAngle TablePhysics::Angle() {
  std::lock_guard lock(mutex_);
  AdvanceTo(clock_.NowNs());
  const double counts_per_rad =
      static_cast<double>(options_.encoder_counts_per_rev) / (2.0 * std::numbers::pi);
  const double read_rad = angle_rad_ + options_.encoder_noise_rad * encoder_normal_(encoder_rng_);
  // floor: an encoder counts edges, so the count changes when the angle crosses one. int64 holds
  // 1e12 rad of 2^23 counts/rev; the conversion to uint32 is modulo 2^32 (negative angles wrap).
  const auto count = static_cast<std::int64_t>(std::floor(read_rad * counts_per_rad));
  hw::RateTableAngle a;
  a.t_ns = t_ns_;
  a.window_ns = 0;
  a.count = static_cast<std::uint32_t>(count);
  a.counts_per_rev = options_.encoder_counts_per_rev;
  a.valid = true;
  return a;
}

double TablePhysics::TrueAngleRad() {
  std::lock_guard lock(mutex_);
  AdvanceTo(clock_.NowNs());
  return angle_rad_;
}

hw::RateTableMode TablePhysics::ActiveMode() {
  std::lock_guard lock(mutex_);
  AdvanceTo(clock_.NowNs());
  return mode_;
}

std::uint16_t TablePhysics::LatchedFaultCode() {
  std::lock_guard lock(mutex_);
  AdvanceTo(clock_.NowNs());
  return fault_code_;
}

double TablePhysics::accel_limit_rad_s2() const {
  std::lock_guard lock(mutex_);
  return accel_rad_s2_;
}

std::uint16_t TablePhysics::watchdog_ms() const {
  std::lock_guard lock(mutex_);
  return watchdog_ms_;
}

}  // namespace hrgbench::drivers::sim
