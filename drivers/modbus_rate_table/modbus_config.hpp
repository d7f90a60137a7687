#pragma once
// Configuration of the Modbus rate table driver: the link, the timing and the software limits.
// Every field has a default and a reason; IsValid() names the first bad field and its value.

#include <cstdint>
#include <string>

#include "modbus_rate_table/rate_limits.hpp"

namespace hrgbench::drivers::modbus_rate_table {

enum class ModbusTransport { kTcp, kRtu };

struct ModbusRateTableConfig {
  ModbusTransport transport = ModbusTransport::kTcp;
  // TCP: the table's controller; 502 is the registered Modbus port.
  std::string host = "127.0.0.1";
  int port = 502;
  // RTU: serial line settings as printed on the controller; 8N1 at 115200 is the common default.
  std::string serial_device = "/dev/ttyUSB0";
  int baud = 115200;
  char parity = 'N';  // 'N', 'E' or 'O'
  int data_bits = 8;
  int stop_bits = 1;
  // Modbus unit (slave) id: 1..247. TCP controllers usually ignore it; RTU needs it.
  int unit_id = 1;

  // A status read takes < 5 ms on a healthy link (see the README's round trip figure); 200 ms
  // absorbs a loaded controller without letting a dead one stall the sequencer.
  int response_timeout_ms = 200;
  // Gap allowed between bytes of one reply; only matters on RTU (at 9600 baud a byte is ~1 ms).
  int byte_timeout_ms = 50;
  // Each Modbus transaction is tried this many times on timeout, bad reply or lost connection
  // (never on an exception reply, which is a definite answer). libmodbus' own error recovery is
  // left OFF: MODBUS_ERROR_RECOVERY_LINK reconnects forever.
  int transaction_attempts = 2;
  // Connect / reconnect: attempts and pause between them. Bounded: at most
  // connect_attempts x (response_timeout_ms + reconnect_backoff_ms).
  int connect_attempts = 3;
  int reconnect_backoff_ms = 100;

  // The table stops itself when no heartbeat arrives for watchdog_timeout_ms (written at
  // Connect). The driver writes one when heartbeat_period_ms has passed, on any call; 5 periods
  // per timeout survive a few lost transactions.
  int watchdog_timeout_ms = 1000;
  int heartbeat_period_ms = 200;

  // Acceleration limit written at Connect (rad/s^2); a gentle default for a gyro on the top.
  double accel_limit_rad_s2 = 1.0;
  RateLimits limits;

  // SafeStop() gives up after this (plus one transaction's timeout); the watchdog is the fallback.
  int safe_stop_budget_ms = 1000;

  bool IsValid(std::string* why) const;
  // "tcp 127.0.0.1:502 unit 1" or "rtu /dev/ttyUSB0 115200 8N1 unit 1"
  std::string Describe() const;
};

}  // namespace hrgbench::drivers::modbus_rate_table
