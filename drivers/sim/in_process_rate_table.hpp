#pragma once
// InProcessRateTable: hw::RateTable directly on a TablePhysics (drivers/sim), no Modbus: the rate
// table of the in-process simulated station. It keeps the real driver's (ModbusRateTable) semantics
// for everything the bench observes, and reuses the real driver's pure pieces rather than copies:
//   - software limits (modbus_rate_table/rate_limits.hpp) checked BEFORE the table is commanded;
//   - "rate stable" (modbus_rate_table/stable_wait.hpp, StableDetector + WaitForStableRate): the
//     table's stable bit AND |measured - target| <= tolerance AND no fault, for the dwell;
//   - the state machine disconnected -> connected <-> faulted (a fault seen in a status; left when
//     a status after ResetFault shows none) -> disconnected (connection lost);
//   - the heartbeat written when due by every call (heartbeat_period_ms), the watchdog written and
//     read back at Connect, SafeStop within a budget and noexcept.
// A hardware refusal (rate beyond the table's own limit, accel above its maximum, a command while
// faulted) is kExceptionReply (kFaulted when the table is faulted), as the Modbus table answers.
//
// Failure injection (STYLE rule 6), explicit and counted: never stable, a fault latched at a
// scheduled time, the next K calls failing (timeout or lost connection), unresponsive from a
// scheduled time on. A timeout costs transaction_attempts x response_timeout_ms of the clock's
// time, as on the wire, so the bench's time budgets see it.
//
// Units: rad/s, rad/s^2, ms / s / ns as named. Time base: the injected Clock (the station's).
// Threads: owned by one thread (the sequencer's). counters(), state() and SenseTrueRateRadS() may
// be called from any thread (atomics; TablePhysics is thread-safe). Not real-time safe.

#include <atomic>
#include <cstdint>
#include <expected>
#include <string>

#include "hrgbench/hw/clock.hpp"
#include "hrgbench/hw/rate_table.hpp"
#include "modbus_rate_table/link_state.hpp"
#include "modbus_rate_table/rate_limits.hpp"
#include "sim/table_physics.hpp"

namespace hrgbench::drivers::sim_station {

// Every injected failure is off by default. Times are seconds on the clock from the table's
// construction (the station's start); < 0 means never.
struct InProcessTableFaults {
  bool never_stable = false;           // the table's own at-rate bit never comes (a hunting loop)
  double fault_after_s = -1.0;         // the drive faults (kDrive, latched) at this time
  double unresponsive_after_s = -1.0;  // from this time on every call times out
  std::uint32_t fail_next_calls = 0;   // the next N calls fail with fail_code (then recover)
  hw::RateTableErrorCode fail_code = hw::RateTableErrorCode::kTimeout;  // or kConnectionLost
};

struct InProcessRateTableConfig {
  modbus_rate_table::RateLimits limits;      // software limits (the bench's ceiling)
  double accel_limit_rad_s2 = 1.0;           // written and read back at Connect
  std::uint16_t watchdog_timeout_ms = 1000;  // written and read back at Connect (100..60000)
  std::int64_t heartbeat_period_ms = 200;    // every call heartbeats when this has passed
  std::int64_t response_timeout_ms = 200;    // what one timed-out attempt costs
  int transaction_attempts = 2;              // attempts per call before a timeout is reported
  std::int64_t safe_stop_budget_ms = 1000;   // SafeStop gives up after this
  InProcessTableFaults faults;

  bool IsValid(std::string* why) const;
};

// The link state machine is the Modbus table's (the same observable semantics).
using modbus_rate_table::TableLinkState;

// The last motion command the bench sent (SetRate, Stop or SafeStop), whether or not the table
// received it: what a test checks to know the bench commanded zero rate, even when the table no
// longer answers (then `delivered` is false and the table's watchdog is what stops it).
struct SentTableCommand {
  hw::RateTableMode mode = hw::RateTableMode::kIdle;
  double rate_rad_s = 0.0;
  std::int64_t sent_at_ns = -1;  // the station's clock; -1: nothing sent yet
  bool delivered = false;
  bool safe_stop = false;  // sent by SafeStop
};

// One counter per failure kind (STYLE rule 5), cumulative, never reset.
struct InProcessTableCounters {
  std::uint64_t calls = 0;              // calls that reached the table (the wire's transactions)
  std::uint64_t timeouts = 0;           // calls that timed out (injected)
  std::uint64_t connection_losses = 0;  // calls that lost the connection (injected)
  std::uint64_t limit_rejections = 0;   // software limit refused a value (nothing commanded)
  std::uint64_t refusals = 0;           // the table refused a command (hardware limit, fault)
  std::uint64_t heartbeats = 0;         // heartbeats delivered
  std::uint64_t faults_injected = 0;    // scheduled faults that fired
};

class InProcessRateTable final : public hw::RateTable {
 public:
  // `physics` and `clock` must outlive this; `clock` must be the physics' clock. The config is
  // validated by Connect() (kInvalidConfig).
  InProcessRateTable(InProcessRateTableConfig config, sim::TablePhysics& physics, hw::Clock& clock);

  std::expected<void, hw::RateTableError> Connect() override;
  std::expected<void, hw::RateTableError> SetRate(double rate_rad_s) override;
  std::expected<void, hw::RateTableError> SetAccelerationLimit(double accel_rad_s2) override;
  std::expected<hw::RateTableStatus, hw::RateTableError> ReadStatus() override;
  // The physics' encoder (TablePhysics::Angle: quantised, with read noise) sampled at the clock's
  // now: window_ns = 0, as an ideal time stamp. One call, like ReadStatus (failures injected the
  // same way).
  std::expected<hw::RateTableAngle, hw::RateTableError> ReadAngle() override;
  std::expected<hw::RateTableStatus, hw::RateTableError> WaitUntilStable(
      const hw::StableCriteria& criteria) override;
  std::expected<void, hw::RateTableError> Heartbeat() override;
  std::expected<void, hw::RateTableError> ResetFault() override;
  std::expected<void, hw::RateTableError> Stop() override;
  // Returns within safe_stop_budget_ms of the clock (+ one response timeout). Never throws.
  void SafeStop() noexcept override;
  void Disconnect() noexcept override;

  // Failure injection at run time (owner thread): the next `count` calls fail with `code`
  // (kTimeout or kConnectionLost).
  void FailNextCalls(std::uint32_t count, hw::RateTableErrorCode code);
  void SetNeverStable(bool never_stable) noexcept { never_stable_ = never_stable; }

  // The noiseless table rate a gyro on the top senses, after firing a scheduled fault that is due
  // (so the fault takes effect on the physics even when the owner does not call). Any thread.
  double SenseTrueRateRadS();

  TableLinkState state() const noexcept { return state_.load(std::memory_order_acquire); }
  InProcessTableCounters counters() const noexcept;
  double target_rate_rad_s() const noexcept { return target_rate_rad_s_; }
  // Owner thread, or after the owner is done.
  const SentTableCommand& last_command() const noexcept { return last_command_; }
  const InProcessRateTableConfig& config() const noexcept { return config_; }

 private:
  // The wire's part of a call: injected failures, then the heartbeat when due.
  std::expected<void, hw::RateTableError> Transact(const char* what);
  std::expected<void, hw::RateTableError> RequireConnected(bool allow_faulted) const;
  std::expected<void, hw::RateTableError> Refused(const char* what);
  bool InjectedFailureDue() noexcept;  // consumes one pending failure when due
  void FireScheduledFault() noexcept;  // any thread

  InProcessRateTableConfig config_;
  sim::TablePhysics& physics_;
  hw::Clock& clock_;
  const std::int64_t fault_at_ns_;         // INT64_MAX: never
  const std::int64_t unresponsive_at_ns_;  // INT64_MAX: never
  std::atomic<bool> fault_fired_{false};
  std::atomic<TableLinkState> state_{TableLinkState::kDisconnected};
  std::uint32_t fail_next_calls_;
  hw::RateTableErrorCode fail_code_;
  bool never_stable_;
  std::int64_t last_heartbeat_ns_ = 0;
  std::uint16_t heartbeat_value_ = 0;
  double target_rate_rad_s_ = 0.0;
  SentTableCommand last_command_;

  struct AtomicCounters {
    std::atomic<std::uint64_t> calls{0}, timeouts{0}, connection_losses{0}, limit_rejections{0},
        refusals{0}, heartbeats{0}, faults_injected{0};
  } counters_;
};

}  // namespace hrgbench::drivers::sim_station
