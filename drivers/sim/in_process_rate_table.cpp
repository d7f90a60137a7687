#include "sim/in_process_rate_table.hpp"

#include <cmath>
#include <limits>

#include "hrgbench/hw/error_text.hpp"
#include "modbus_rate_table/stable_wait.hpp"

namespace hrgbench::drivers::sim_station {

namespace {
using hw::RateTableError;
using hw::RateTableErrorCode;

constexpr std::int64_t kNsPerMs = 1'000'000;
constexpr std::int64_t kNever = std::numeric_limits<std::int64_t>::max();

std::unexpected<RateTableError> Fail(RateTableErrorCode code, std::string message) {
  return std::unexpected(RateTableError{code, std::move(message)});
}

std::int64_t AtNs(std::int64_t start_ns, double after_s) {
  if (!(after_s >= 0.0) || !std::isfinite(after_s)) return kNever;
  return start_ns + hw::SecondsToNs(after_s);
}

}  // namespace

bool InProcessRateTableConfig::IsValid(std::string* why) const {
  const auto fail = [why](std::string message) {
    if (why != nullptr) *why = std::move(message);
    return false;
  };
  if (!limits.IsValid(why)) return false;
  if (!(std::isfinite(accel_limit_rad_s2) && accel_limit_rad_s2 > 0.0 &&
        accel_limit_rad_s2 <= limits.max_accel_rad_s2)) {
    return fail(hw::ErrorText("accel_limit_rad_s2 must be in (0, max_accel_rad_s2 = ",
                              limits.max_accel_rad_s2, "], got ", accel_limit_rad_s2));
  }
  if (watchdog_timeout_ms < 100 || watchdog_timeout_ms > 60000) {
    return fail(
        hw::ErrorText("watchdog_timeout_ms must be in [100, 60000], got ", watchdog_timeout_ms));
  }
  if (heartbeat_period_ms <= 0 || 2 * heartbeat_period_ms > watchdog_timeout_ms) {
    return fail(hw::ErrorText("heartbeat_period_ms must be in (0, watchdog_timeout_ms / 2 = ",
                              watchdog_timeout_ms / 2, "], got ", heartbeat_period_ms));
  }
  if (response_timeout_ms <= 0) {
    return fail(hw::ErrorText("response_timeout_ms must be > 0, got ", response_timeout_ms));
  }
  if (transaction_attempts < 1) {
    return fail(hw::ErrorText("transaction_attempts must be >= 1, got ", transaction_attempts));
  }
  if (safe_stop_budget_ms <= 0) {
    return fail(hw::ErrorText("safe_stop_budget_ms must be > 0, got ", safe_stop_budget_ms));
  }
  if (faults.fail_code != RateTableErrorCode::kTimeout &&
      faults.fail_code != RateTableErrorCode::kConnectionLost) {
    return fail("faults.fail_code must be kTimeout or kConnectionLost");
  }
  return true;
}

InProcessRateTable::InProcessRateTable(InProcessRateTableConfig config, sim::TablePhysics& physics,
                                       hw::Clock& clock)
    : config_(std::move(config)),
      physics_(physics),
      clock_(clock),
      fault_at_ns_(AtNs(clock.NowNs(), config_.faults.fault_after_s)),
      unresponsive_at_ns_(AtNs(clock.NowNs(), config_.faults.unresponsive_after_s)),
      fail_next_calls_(config_.faults.fail_next_calls),
      fail_code_(config_.faults.fail_code),
      never_stable_(config_.faults.never_stable) {}

InProcessTableCounters InProcessRateTable::counters() const noexcept {
  const auto get = [](const std::atomic<std::uint64_t>& c) {
    return c.load(std::memory_order_relaxed);
  };
  return {get(counters_.calls),
          get(counters_.timeouts),
          get(counters_.connection_losses),
          get(counters_.limit_rejections),
          get(counters_.refusals),
          get(counters_.heartbeats),
          get(counters_.faults_injected)};
}

void InProcessRateTable::FailNextCalls(std::uint32_t count, hw::RateTableErrorCode code) {
  fail_next_calls_ = count;
  fail_code_ = code == RateTableErrorCode::kConnectionLost ? code : RateTableErrorCode::kTimeout;
}

void InProcessRateTable::FireScheduledFault() noexcept {
  if (fault_at_ns_ == kNever || fault_fired_.load(std::memory_order_acquire)) return;
  if (clock_.NowNs() < fault_at_ns_) return;
  if (fault_fired_.exchange(true, std::memory_order_acq_rel)) return;  // another thread fired it
  physics_.InjectFault(hw::RateTableFault::kDrive);
  ++counters_.faults_injected;
}

double InProcessRateTable::SenseTrueRateRadS() {
  FireScheduledFault();
  return physics_.TrueRateRadS();
}

bool InProcessRateTable::InjectedFailureDue() noexcept {
  if (clock_.NowNs() >= unresponsive_at_ns_) return true;
  if (fail_next_calls_ == 0) return false;
  --fail_next_calls_;
  return true;
}

std::expected<void, RateTableError> InProcessRateTable::RequireConnected(bool allow_faulted) const {
  return modbus_rate_table::RequireLinkState(state(), allow_faulted, "in-process rate table");
}

std::expected<void, RateTableError> InProcessRateTable::Transact(const char* what) {
  FireScheduledFault();
  ++counters_.calls;
  const bool unresponsive = clock_.NowNs() >= unresponsive_at_ns_;
  if (InjectedFailureDue()) {
    if (!unresponsive && fail_code_ == RateTableErrorCode::kConnectionLost) {
      // The real driver's bounded reconnects failed: it gives the link up.
      ++counters_.connection_losses;
      state_.store(TableLinkState::kDisconnected, std::memory_order_release);
      return Fail(RateTableErrorCode::kConnectionLost,
                  hw::ErrorText(what, ": connection to the in-process table lost (injected)"));
    }
    // Every attempt waits its full response timeout, as on the wire.
    clock_.SleepForNs(config_.transaction_attempts * config_.response_timeout_ms * kNsPerMs);
    ++counters_.timeouts;
    return Fail(RateTableErrorCode::kTimeout,
                hw::ErrorText(what, ": no reply within ", config_.response_timeout_ms, " ms after ",
                              config_.transaction_attempts, " attempts (injected",
                              unresponsive ? ": table unresponsive)" : ")"));
  }
  if (clock_.NowNs() - last_heartbeat_ns_ >= config_.heartbeat_period_ms * kNsPerMs) {
    physics_.Heartbeat(++heartbeat_value_);
    last_heartbeat_ns_ = clock_.NowNs();
    ++counters_.heartbeats;
  }
  return {};
}

std::expected<void, RateTableError> InProcessRateTable::Refused(const char* what) {
  ++counters_.refusals;
  const hw::RateTableStatus status = physics_.Status();
  if (status.fault || status.estop) {
    state_.store(TableLinkState::kFaulted, std::memory_order_release);
    return Fail(RateTableErrorCode::kFaulted,
                hw::ErrorText(what, " refused: table reports fault '",
                              hw::RateTableFaultName(status.fault_code), "'"));
  }
  return Fail(RateTableErrorCode::kExceptionReply,
              hw::ErrorText(what, " refused by the table (beyond its hardware limits)"));
}

std::expected<void, RateTableError> InProcessRateTable::Connect() {
  std::string why;
  if (!config_.IsValid(&why)) return Fail(RateTableErrorCode::kInvalidConfig, why);
  Disconnect();
  state_.store(TableLinkState::kConnected, std::memory_order_release);
  last_heartbeat_ns_ = std::numeric_limits<std::int64_t>::min() / 2;  // due at once
  if (auto ok = Transact("connect"); !ok) {
    Disconnect();
    return Fail(RateTableErrorCode::kConnectFailed, ok.error().message);
  }
  if (!physics_.SetAccelLimit(config_.accel_limit_rad_s2) ||
      !physics_.SetWatchdogMs(config_.watchdog_timeout_ms)) {
    Disconnect();
    return Refused("connect: acceleration limit / watchdog setting");
  }
  // Read-back, as the real driver does after its setup write.
  if (physics_.accel_limit_rad_s2() != config_.accel_limit_rad_s2 ||
      physics_.watchdog_ms() != config_.watchdog_timeout_ms) {
    Disconnect();
    return Fail(RateTableErrorCode::kReadBackMismatch,
                hw::ErrorText("connect: wrote accel ", config_.accel_limit_rad_s2,
                              " rad/s^2, watchdog ", config_.watchdog_timeout_ms, " ms; read back ",
                              physics_.accel_limit_rad_s2(), ", ", physics_.watchdog_ms()));
  }
  const hw::RateTableStatus status = physics_.Status();
  target_rate_rad_s_ = status.commanded_rate_rad_s;
  if (status.fault || status.estop) {
    state_.store(TableLinkState::kFaulted, std::memory_order_release);
  }
  return {};
}

std::expected<void, RateTableError> InProcessRateTable::SetRate(double rate_rad_s) {
  if (auto ok = modbus_rate_table::CheckRate(config_.limits, rate_rad_s); !ok) {
    ++counters_.limit_rejections;
    return ok;
  }
  if (auto ok = RequireConnected(/*allow_faulted=*/false); !ok) return ok;
  last_command_ = {hw::RateTableMode::kRate, rate_rad_s, clock_.NowNs(), false, false};
  if (auto ok = Transact("set rate"); !ok) return ok;
  last_command_.delivered = true;
  if (!physics_.Command(hw::RateTableMode::kRate, rate_rad_s)) return Refused("set rate");
  target_rate_rad_s_ = rate_rad_s;
  return {};
}

std::expected<void, RateTableError> InProcessRateTable::SetAccelerationLimit(double accel_rad_s2) {
  if (auto ok = modbus_rate_table::CheckAcceleration(config_.limits, accel_rad_s2); !ok) {
    ++counters_.limit_rejections;
    return ok;
  }
  if (auto ok = RequireConnected(/*allow_faulted=*/false); !ok) return ok;
  if (auto ok = Transact("set acceleration limit"); !ok) return ok;
  if (!physics_.SetAccelLimit(accel_rad_s2)) return Refused("set acceleration limit");
  if (physics_.accel_limit_rad_s2() != accel_rad_s2) {
    return Fail(RateTableErrorCode::kReadBackMismatch,
                hw::ErrorText("acceleration limit: wrote ", accel_rad_s2, " rad/s^2, read back ",
                              physics_.accel_limit_rad_s2()));
  }
  return {};
}

std::expected<hw::RateTableStatus, RateTableError> InProcessRateTable::ReadStatus() {
  if (auto ok = RequireConnected(/*allow_faulted=*/true); !ok) return std::unexpected(ok.error());
  if (auto ok = Transact("read status"); !ok) return std::unexpected(ok.error());
  hw::RateTableStatus status = physics_.Status();
  if (never_stable_) status.rate_stable = false;
  state_.store(status.fault || status.estop ? TableLinkState::kFaulted : TableLinkState::kConnected,
               std::memory_order_release);
  return status;
}

std::expected<hw::RateTableAngle, RateTableError> InProcessRateTable::ReadAngle() {
  if (auto ok = RequireConnected(/*allow_faulted=*/true); !ok) return std::unexpected(ok.error());
  if (auto ok = Transact("read angle"); !ok) return std::unexpected(ok.error());
  return physics_.Angle();
}

std::expected<hw::RateTableStatus, RateTableError> InProcessRateTable::WaitUntilStable(
    const hw::StableCriteria& criteria) {
  if (auto ok = RequireConnected(/*allow_faulted=*/true); !ok) return std::unexpected(ok.error());
  return modbus_rate_table::WaitForStableRate([this] { return ReadStatus(); }, clock_,
                                              target_rate_rad_s_, criteria);
}

std::expected<void, RateTableError> InProcessRateTable::Heartbeat() {
  if (auto ok = RequireConnected(/*allow_faulted=*/true); !ok) return ok;
  last_heartbeat_ns_ = std::numeric_limits<std::int64_t>::min() / 2;  // write one now
  return Transact("heartbeat");
}

std::expected<void, RateTableError> InProcessRateTable::ResetFault() {
  if (auto ok = RequireConnected(/*allow_faulted=*/true); !ok) return ok;
  if (auto ok = Transact("fault reset"); !ok) return ok;
  physics_.ResetFault();
  if (auto status = ReadStatus(); !status) return std::unexpected(status.error());
  return {};
}

std::expected<void, RateTableError> InProcessRateTable::Stop() {
  if (auto ok = RequireConnected(/*allow_faulted=*/true); !ok) return ok;
  target_rate_rad_s_ = 0.0;
  last_command_ = {hw::RateTableMode::kIdle, 0.0, clock_.NowNs(), false, false};
  if (auto ok = Transact("stop"); !ok) return ok;
  last_command_.delivered = true;
  if (!physics_.Command(hw::RateTableMode::kIdle, 0.0)) return Refused("stop");
  return {};
}

void InProcessRateTable::SafeStop() noexcept {
  try {
    target_rate_rad_s_ = 0.0;
    last_command_ = {hw::RateTableMode::kIdle, 0.0, clock_.NowNs(), false, true};
    const std::int64_t deadline_ns = clock_.NowNs() + config_.safe_stop_budget_ms * kNsPerMs;
    // Whatever the state machine says: a stop is always worth trying, within one budget.
    do {
      ++counters_.calls;
      if (!InjectedFailureDue()) {
        physics_.Command(hw::RateTableMode::kIdle, 0.0);
        last_command_.delivered = true;
        return;
      }
      ++counters_.timeouts;
      clock_.SleepForNs(config_.response_timeout_ms * kNsPerMs);
    } while (clock_.NowNs() < deadline_ns);
  } catch (...) {
    // Only std::bad_alloc could get here; the table's watchdog is the second line of defence.
  }
}

void InProcessRateTable::Disconnect() noexcept {
  state_.store(TableLinkState::kDisconnected, std::memory_order_release);
}

}  // namespace hrgbench::drivers::sim_station
