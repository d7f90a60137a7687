#pragma once
// TablePhysics: the simulated rate table's mechanics and safety logic, independent of any protocol.
// The Modbus server (modbus_table_server.hpp) exposes it on the wire; an in-process simulated
// station or the simulated gyro reads it directly (TrueRateRadS).
//
// Model (one axis), integrated in steps of at most step_s on the injected Clock's time:
//   setpoint ramp r:   slews toward the target at the acceleration limit (rad/s^2)
//   table rate w:      first-order lag behind r, time constant settle_time_constant_s:
//                      w += (r - w) (1 - exp(-dt / tau))   (exact for r constant over dt)
//   measured rate:     w + N(0, noise_rad_s^2), drawn per Status() from a mt19937_64 seeded
//                      with `seed` (libstdc++'s normal_distribution: reproducible on this
//                      toolchain for the same sequence of calls and times).
//   table angle:       phi += integral of w over the step, exactly for the lag above with r held:
//                      r dt + (w - r) tau (1 - exp(-dt / tau))
//   encoder count:     floor((phi + N(0, encoder_noise_rad^2)) / q) modulo 2^32,
//                      q = 2 pi / encoder_counts_per_rev; the read noise from a second generator
//                      (seed_seq {seed, 2}), so reading the angle leaves the rate noise's sequence
//                      as it was. phi starts at 0 (the count at 0) when the table is made.
// Target is the commanded rate in rate mode and 0 in idle or when faulted.
// Safety: watchdog (rate mode without a heartbeat for watchdog_ms -> fault kWatchdog, ramp to 0),
// e-stop (fault kEStop, ramp to 0 at estop_decel_rad_s2), interlock (commanding motion while open,
// or opening while moving -> fault kInterlock), overspeed (|w| > 1.1 max_rate -> kOverspeed).
// Faults latch until ResetFault() (which keeps kEStop while the e-stop is pressed).
// Own "rate stable" bit: rate mode, no fault, ramp at target and |w - target| <= tolerance, for
// stable_hold_s.
//
// Thread-safe: every method locks one mutex (the server thread and an in-process reader may call
// concurrently). Not real-time safe (mutex).

#include <cstdint>
#include <mutex>
#include <random>
#include <string>

#include "hrgbench/hw/clock.hpp"
#include "hrgbench/hw/rate_table.hpp"

namespace hrgbench::drivers::sim {

struct TablePhysicsOptions {
  double max_rate_rad_s = 20.0;          // hardware limit: commands beyond it are refused
  double accel_limit_rad_s2 = 1.0;       // power-on acceleration limit
  double max_accel_rad_s2 = 50.0;        // the drive cannot be set above this
  double settle_time_constant_s = 0.05;  // rate-loop lag; a few tens of ms on a real table
  double noise_rad_s = 2e-5;             // encoder-derived rate noise, 1 sigma
  std::uint64_t seed = 1;
  double stable_tolerance_rad_s = 1e-3;  // the table's own at-rate window (vendor's choice)
  double stable_hold_s = 0.2;
  double motion_threshold_rad_s = 1e-4;  // |w| above this sets "in motion"
  double estop_decel_rad_s2 = 20.0;      // braking under e-stop
  std::uint16_t watchdog_ms = 1000;      // power-on watchdog timeout
  double temperature_c = 25.0;
  double step_s = 1e-3;  // integration step
  // The table top's encoder: 2^23 counts/rev (0.15 arcsec) is a usual rate-table encoder after
  // interpolation; its read noise, 1 sigma before quantisation, about 0.2 arcsec.
  std::uint32_t encoder_counts_per_rev = 1u << 23;
  double encoder_noise_rad = 1e-6;

  bool IsValid(std::string* why) const;
};

class TablePhysics {
 public:
  // `clock` must outlive this; time starts at clock.NowNs().
  TablePhysics(TablePhysicsOptions options, const hw::Clock& clock);

  // Rate command (rad/s). False when refused: |rate| > max_rate or not finite, a latched fault, or
  // the interlock open (which also trips kInterlock). Switching to rate mode restarts the
  // watchdog window.
  bool Command(hw::RateTableMode mode, double rate_rad_s);
  bool SetAccelLimit(double accel_rad_s2);        // false when <= 0, > max_accel or not finite
  bool SetWatchdogMs(std::uint16_t watchdog_ms);  // false outside 100..60000
  void Heartbeat(std::uint16_t value);
  void ResetFault();
  void SetEStop(bool pressed);
  void SetInterlockOpen(bool open);
  void InjectFault(hw::RateTableFault fault);  // e.g. kDrive: trips like a real drive fault

  // Advances to the clock's now and reports (t_ns = now; measured rate includes noise).
  hw::RateTableStatus Status();
  // Advances to now; the noiseless table rate (what a gyro on the top senses).
  double TrueRateRadS();
  // Advances to now and reads the encoder: t_ns = now, window_ns = 0 (sampled at now), the count
  // with read noise and quantisation, valid = true.
  hw::RateTableAngle Angle();
  // Advances to now; the table angle itself (rad since construction, unwrapped, no noise).
  double TrueAngleRad();
  // Advance to now without drawing noise (the Modbus server asks before every request, and must
  // not change the seeded noise sequence the status reads see). ActiveMode: the mode the table is
  // in (kIdle once a fault trips, whatever was commanded). LatchedFaultCode: the RateTableFault
  // latched, 0 for none (a pressed e-stop is kEStop); while it is set Command(kRate) is refused.
  hw::RateTableMode ActiveMode();
  std::uint16_t LatchedFaultCode();

  double accel_limit_rad_s2() const;
  std::uint16_t watchdog_ms() const;
  const TablePhysicsOptions& options() const { return options_; }

 private:
  void AdvanceTo(std::int64_t now_ns);  // requires mutex_
  void Trip(hw::RateTableFault fault);  // requires mutex_

  const TablePhysicsOptions options_;
  const hw::Clock& clock_;
  mutable std::mutex mutex_;
  hw::RateTableMode mode_ = hw::RateTableMode::kIdle;
  double target_rad_s_ = 0.0;
  double ramp_rad_s_ = 0.0;
  double rate_rad_s_ = 0.0;
  double angle_rad_ = 0.0;  // relative precision 1e-16: 1e-10 rad after a day at 10 rad/s
  double accel_rad_s2_;
  std::uint16_t watchdog_ms_;
  std::int64_t t_ns_;
  std::int64_t last_heartbeat_ns_;
  std::uint16_t heartbeat_echo_ = 0;
  std::uint16_t fault_code_ = 0;
  bool estop_ = false;
  bool interlock_open_ = false;
  bool stable_ = false;
  bool stable_window_open_ = false;
  std::int64_t stable_since_ns_ = 0;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::mt19937_64 encoder_rng_;
  std::normal_distribution<double> encoder_normal_{0.0, 1.0};
};

}  // namespace hrgbench::drivers::sim
