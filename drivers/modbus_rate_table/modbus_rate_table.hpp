#pragma once
// ModbusRateTable: RateTable over Modbus TCP or RTU (libmodbus), speaking the register map in
// README.md / register_map.hpp.
//
// State machine (state()):
//   kDisconnected --Connect() ok--> kConnected | kFaulted (if the table reports a fault)
//   kConnected --status with fault bit--> kFaulted --ResetFault() + clean status--> kConnected
//   any --transport failure after bounded reconnects, or Disconnect()--> kDisconnected
// SetRate/SetAccelerationLimit are refused in kFaulted (kFaulted, nothing sent) and
// kDisconnected (kNotConnected). Stop, ReadStatus, Heartbeat and ResetFault work in kFaulted.
// When the table faulted since the last status, SetRate is sent and the table refuses it with
// exception 04 (SERVER DEVICE FAILURE): the driver reads one status and, when it shows a fault or
// e-stop, returns kFaulted naming the fault (state kFaulted); otherwise kExceptionReply. Never
// retried. Stop and SafeStop (mode 0, rate 0) are accepted by the table in every state.
//
// Thread: owned by one thread; its libmodbus context is never shared (one context per thread: a
// second thread that needs the table, e.g. a monitor, opens its own ModbusRateTable). counters()
// and state() may be read from any thread.
//
// Heartbeat: the table's watchdog (watchdog_timeout_ms, written at Connect) stops it when no
// heartbeat arrives. Every call of this driver writes one first when heartbeat_period_ms has
// passed since the last; the sequencer calls Heartbeat() (or ReadStatus()) at least every
// heartbeat_period_ms while the table moves and nothing else is being called.
//
// Time bounds: every transaction <= transaction_attempts x response_timeout_ms (+ reconnects,
// each <= response_timeout_ms + reconnect_backoff_ms). SafeStop() <= safe_stop_budget_ms +
// response_timeout_ms, and at most kSafeStopAttempts connections or writes, each failed one
// followed by a pause doubling from 10 ms to reconnect_backoff_ms.

#include <atomic>
#include <cstdint>
#include <memory>
#include <span>

#include "hrgbench/hw/clock.hpp"
#include "hrgbench/hw/rate_table.hpp"
#include "modbus_rate_table/link_state.hpp"
#include "modbus_rate_table/modbus_config.hpp"

namespace hrgbench::drivers::modbus_rate_table {

class ModbusLink;
struct LinkResult;

// One counter per failure kind, plus the totals they are relative to.
struct ModbusTableCounters {
  std::uint64_t transactions = 0;       // Modbus requests sent (including retries)
  std::uint64_t timeouts = 0;           // no reply / reply after response_timeout_ms
  std::uint64_t exception_replies = 0;  // Modbus exception answers
  std::uint64_t bad_replies = 0;        // wrong length, CRC, unit id
  std::uint64_t connection_losses = 0;  // socket/device errors
  std::uint64_t reconnects = 0;         // link (re)open attempts after the first Connect
  std::uint64_t limit_rejections = 0;   // software limit refused a value (nothing sent)
  std::uint64_t heartbeats = 0;         // heartbeat writes that succeeded
};

// SafeStop's attempts (connects and writes together) within its budget: enough to ride out a
// table's controller restarting its listener, few enough that a peer that accepts and closes at
// once is not hammered.
inline constexpr int kSafeStopAttempts = 8;

class ModbusRateTable final : public hw::RateTable {
 public:
  // `clock` times heartbeats, dwell windows, back-offs and SafeStop's budget; it must outlive
  // this object. The config is validated by Connect() (kInvalidConfig).
  ModbusRateTable(ModbusRateTableConfig config, hw::Clock& clock);
  ~ModbusRateTable() override;  // closes the link; does NOT command the table (see SafeStop)

  std::expected<void, hw::RateTableError> Connect() override;
  std::expected<void, hw::RateTableError> SetRate(double rate_rad_s) override;
  std::expected<void, hw::RateTableError> SetAccelerationLimit(double accel_rad_s2) override;
  std::expected<hw::RateTableStatus, hw::RateTableError> ReadStatus() override;
  // One FC 04 of the angle block (input 11..15); kNotSupported, without I/O, when the table's map
  // (read at Connect) is version 1. t_ns is the midpoint of the transaction on `clock`.
  std::expected<hw::RateTableAngle, hw::RateTableError> ReadAngle() override;
  std::expected<hw::RateTableStatus, hw::RateTableError> WaitUntilStable(
      const hw::StableCriteria& criteria) override;
  std::expected<void, hw::RateTableError> Heartbeat() override;
  std::expected<void, hw::RateTableError> ResetFault() override;
  std::expected<void, hw::RateTableError> Stop() override;
  void SafeStop() noexcept override;
  void Disconnect() noexcept override;

  TableLinkState state() const noexcept { return state_.load(std::memory_order_acquire); }
  ModbusTableCounters counters() const noexcept;
  const ModbusRateTableConfig& config() const noexcept { return config_; }
  // The rate last commanded by SetRate/Stop: the target WaitUntilStable compares against.
  double target_rate_rad_s() const noexcept { return target_rate_rad_s_; }
  // The register map version the table reported at the last Connect (0 before).
  std::uint16_t map_version() const noexcept { return map_version_; }

 private:
  enum class Op { kReadInput, kReadHolding, kWriteHolding };
  std::expected<void, hw::RateTableError> Transact(Op op, int address,
                                                   std::span<std::uint16_t> regs);
  std::expected<void, hw::RateTableError> Reopen();
  std::expected<void, hw::RateTableError> WriteAndReadBack(int address,
                                                           std::span<const std::uint16_t> regs);
  std::expected<void, hw::RateTableError> WriteHeartbeat();
  std::expected<void, hw::RateTableError> HeartbeatIfDue();
  std::expected<void, hw::RateTableError> RequireConnected(bool allow_faulted) const;
  // SetRate answered with exception 04: kFaulted when a status shows why, else `exception`.
  std::expected<void, hw::RateTableError> RefusedCommand(hw::RateTableError exception,
                                                         double rate_rad_s);
  hw::RateTableError ErrorFrom(const LinkResult& result, const char* what, int address) const;
  void Count(const LinkResult& result) noexcept;

  ModbusRateTableConfig config_;
  hw::Clock& clock_;
  std::unique_ptr<ModbusLink> link_;
  std::atomic<TableLinkState> state_{TableLinkState::kDisconnected};
  std::int64_t last_heartbeat_ns_ = 0;
  std::uint16_t heartbeat_value_ = 0;
  double target_rate_rad_s_ = 0.0;
  std::uint16_t map_version_ = 0;
  int last_exception_code_ = 0;  // of the last Transact that failed with an exception, else 0

  struct AtomicCounters {
    std::atomic<std::uint64_t> transactions{0}, timeouts{0}, exception_replies{0}, bad_replies{0},
        connection_losses{0}, reconnects{0}, limit_rejections{0}, heartbeats{0};
  } counters_;
};

}  // namespace hrgbench::drivers::modbus_rate_table
