#include "modbus_rate_table/modbus_link.hpp"

#include <modbus.h>

#include <cerrno>
#include <chrono>
#include <thread>

namespace hrgbench::drivers::modbus_rate_table {

namespace {
void SetTimeout(modbus_t* ctx, int ms, int (*setter)(modbus_t*, std::uint32_t, std::uint32_t)) {
  setter(ctx, static_cast<std::uint32_t>(ms / 1000), static_cast<std::uint32_t>(ms % 1000) * 1000u);
}
}  // namespace

std::string LinkResult::Describe() const {
  switch (status) {
    case LinkStatus::kOk:
      return "ok";
    case LinkStatus::kTimeout:
      return std::string("timeout (") + modbus_strerror(error_number) + ")";
    case LinkStatus::kException:
      return "exception " + std::to_string(exception_code) + " (" + modbus_strerror(error_number) +
             ")";
    case LinkStatus::kBadReply:
      return std::string("bad reply (") + modbus_strerror(error_number) + ")";
    case LinkStatus::kConnectionLost:
      return std::string("connection lost (") + modbus_strerror(error_number) + ")";
  }
  return "unknown";
}

LinkResult ModbusLink::Open() {
  Close();
  if (config_.transport == ModbusTransport::kTcp) {
    ctx_ = modbus_new_tcp(config_.host.c_str(), config_.port);
  } else {
    ctx_ = modbus_new_rtu(config_.serial_device.c_str(), config_.baud, config_.parity,
                          config_.data_bits, config_.stop_bits);
  }
  if (ctx_ == nullptr) return {LinkStatus::kConnectionLost, errno, 0};
  // Error recovery stays NONE (the default) on purpose; see the header.
  modbus_set_error_recovery(ctx_, MODBUS_ERROR_RECOVERY_NONE);
  modbus_set_slave(ctx_, config_.unit_id);
  SetTimeout(ctx_, config_.response_timeout_ms, modbus_set_response_timeout);
  SetTimeout(ctx_, config_.byte_timeout_ms, modbus_set_byte_timeout);
  if (modbus_connect(ctx_) == -1) {
    const int error_number = errno;
    modbus_free(ctx_);
    ctx_ = nullptr;
    return {LinkStatus::kConnectionLost, error_number, 0};
  }
  return {};
}

void ModbusLink::Close() noexcept {
  if (ctx_ == nullptr) return;
  modbus_close(ctx_);
  modbus_free(ctx_);
  ctx_ = nullptr;
}

LinkResult ModbusLink::Classify(int rc, int expected) const {
  if (rc == expected) return {};
  if (rc >= 0) return {LinkStatus::kBadReply, EMBBADDATA, 0};
  const int e = errno;
  if (e == ETIMEDOUT) return {LinkStatus::kTimeout, e, 0};
  if (e >= EMBXILFUN && e <= EMBXGTAR) return {LinkStatus::kException, e, e - MODBUS_ENOBASE};
  if (e >= EMBBADCRC && e <= EMBBADSLAVE) return {LinkStatus::kBadReply, e, 0};
  // ECONNRESET, EPIPE, EBADF, EIO, ... : the socket or device is unusable.
  return {LinkStatus::kConnectionLost, e, 0};
}

LinkResult ModbusLink::ReadInputRegisters(int address, std::span<std::uint16_t> dest) {
  if (ctx_ == nullptr) return {LinkStatus::kConnectionLost, ENOTCONN, 0};
  const int n = static_cast<int>(dest.size());
  return Classify(modbus_read_input_registers(ctx_, address, n, dest.data()), n);
}

LinkResult ModbusLink::ReadHoldingRegisters(int address, std::span<std::uint16_t> dest) {
  if (ctx_ == nullptr) return {LinkStatus::kConnectionLost, ENOTCONN, 0};
  const int n = static_cast<int>(dest.size());
  return Classify(modbus_read_registers(ctx_, address, n, dest.data()), n);
}

LinkResult ModbusLink::WriteHoldingRegisters(int address, std::span<const std::uint16_t> values) {
  if (ctx_ == nullptr) return {LinkStatus::kConnectionLost, ENOTCONN, 0};
  const int n = static_cast<int>(values.size());
  return Classify(modbus_write_registers(ctx_, address, n, values.data()), n);
}

void ModbusLink::Resynchronise() noexcept {
  if (ctx_ == nullptr) return;
  if (config_.transport == ModbusTransport::kTcp) {
    Close();
    return;
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(config_.response_timeout_ms));
  modbus_flush(ctx_);
}

}  // namespace hrgbench::drivers::modbus_rate_table
