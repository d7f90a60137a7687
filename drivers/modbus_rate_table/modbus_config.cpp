#include "modbus_rate_table/modbus_config.hpp"

#include <sstream>

#include "modbus_rate_table/register_map.hpp"

namespace hrgbench::drivers::modbus_rate_table {

namespace {
bool InRange(const char* name, long long value, long long lo, long long hi, std::string* why) {
  if (value >= lo && value <= hi) return true;
  if (why != nullptr) {
    std::ostringstream os;
    os << name << " must be in [" << lo << ", " << hi << "], got " << value;
    *why = os.str();
  }
  return false;
}
}  // namespace

bool ModbusRateTableConfig::IsValid(std::string* why) const {
  if (transport == ModbusTransport::kTcp) {
    if (host.empty()) {
      if (why != nullptr) *why = "host must not be empty";
      return false;
    }
    if (!InRange("port", port, 1, 65535, why)) return false;
  } else {
    if (serial_device.empty()) {
      if (why != nullptr) *why = "serial_device must not be empty";
      return false;
    }
    if (!InRange("baud", baud, 300, 4000000, why)) return false;
    if (parity != 'N' && parity != 'E' && parity != 'O') {
      if (why != nullptr) *why = std::string("parity must be N, E or O, got ") + parity;
      return false;
    }
    if (!InRange("data_bits", data_bits, 5, 8, why)) return false;
    if (!InRange("stop_bits", stop_bits, 1, 2, why)) return false;
  }
  if (!InRange("unit_id", unit_id, 1, 247, why)) return false;
  if (!InRange("response_timeout_ms", response_timeout_ms, 1, 60000, why)) return false;
  if (!InRange("byte_timeout_ms", byte_timeout_ms, 1, 60000, why)) return false;
  if (!InRange("transaction_attempts", transaction_attempts, 1, 10, why)) return false;
  if (!InRange("connect_attempts", connect_attempts, 1, 10, why)) return false;
  if (!InRange("reconnect_backoff_ms", reconnect_backoff_ms, 0, 10000, why)) return false;
  if (!InRange("watchdog_timeout_ms", watchdog_timeout_ms, kMinWatchdogMs, kMaxWatchdogMs, why)) {
    return false;
  }
  if (!InRange("heartbeat_period_ms", heartbeat_period_ms, 1, watchdog_timeout_ms / 2, why)) {
    return false;
  }
  if (!InRange("safe_stop_budget_ms", safe_stop_budget_ms, 1, 60000, why)) return false;
  if (!limits.IsValid(why)) return false;
  if (auto ok = CheckAcceleration(limits, accel_limit_rad_s2); !ok) {
    if (why != nullptr) *why = "accel_limit_rad_s2: " + ok.error().message;
    return false;
  }
  return true;
}

std::string ModbusRateTableConfig::Describe() const {
  std::ostringstream os;
  if (transport == ModbusTransport::kTcp) {
    os << "tcp " << host << ":" << port;
  } else {
    os << "rtu " << serial_device << " " << baud << " " << data_bits << parity << stop_bits;
  }
  os << " unit " << unit_id;
  return os.str();
}

}  // namespace hrgbench::drivers::modbus_rate_table
