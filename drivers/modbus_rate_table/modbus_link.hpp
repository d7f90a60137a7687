#pragma once
// One libmodbus context (TCP or RTU) with its failures sorted into kinds. Private to the driver;
// it is the only file of the driver that includes <modbus.h>.
//
// Thread: a libmodbus context is not thread-safe; a ModbusLink is used by one thread only.
// Every call is bounded by the configured response/byte timeouts. libmodbus' error recovery stays
// MODBUS_ERROR_RECOVERY_NONE (its default): recovery is the driver's, bounded.

#include <cstdint>
#include <span>
#include <string>

#include "modbus_rate_table/modbus_config.hpp"

struct _modbus;  // libmodbus' opaque context (typedef'd to modbus_t in <modbus.h>)

namespace hrgbench::drivers::modbus_rate_table {

enum class LinkStatus {
  kOk,
  kTimeout,         // no complete reply in time
  kException,       // a Modbus exception reply (exception_code set)
  kBadReply,        // wrong length, CRC, unit id or content
  kConnectionLost,  // socket / device error: reopen before the next transaction
};

struct LinkResult {
  LinkStatus status = LinkStatus::kOk;
  int error_number = 0;          // errno as libmodbus left it
  int exception_code = 0;        // Modbus exception code (1..11) for kException
  std::string Describe() const;  // modbus_strerror text plus the kind
  bool ok() const { return status == LinkStatus::kOk; }
};

class ModbusLink {
 public:
  explicit ModbusLink(ModbusRateTableConfig config) : config_(std::move(config)) {}
  ~ModbusLink() { Close(); }
  ModbusLink(const ModbusLink&) = delete;
  ModbusLink& operator=(const ModbusLink&) = delete;

  // Creates the context and connects once (TCP connect is bounded by the response timeout).
  LinkResult Open();
  void Close() noexcept;
  bool IsOpen() const noexcept { return ctx_ != nullptr; }

  LinkResult ReadInputRegisters(int address, std::span<std::uint16_t> dest);
  LinkResult ReadHoldingRegisters(int address, std::span<std::uint16_t> dest);
  LinkResult WriteHoldingRegisters(int address, std::span<const std::uint16_t> values);

  // After a timeout or bad reply a late answer may still arrive and be taken for the reply to
  // the next request. TCP: close (the next transaction reopens). RTU: wait one response timeout
  // for the line to go quiet, then flush. Bounded by response_timeout_ms.
  void Resynchronise() noexcept;

 private:
  LinkResult Classify(int rc, int expected) const;

  ModbusRateTableConfig config_;
  _modbus* ctx_ = nullptr;
};

}  // namespace hrgbench::drivers::modbus_rate_table
