#pragma once
// A rate table as the bench sees one of register map version 1 (drivers/modbus_rate_table/
// README.md, "Versions"): every call is forwarded to a real hw::RateTable (the simulated
// station's), but ReadAngle answers kNotSupported without asking it, as ModbusRateTable does on a
// version 1 table. Counts the angle reads it refused.

#include <cstdint>
#include <expected>

#include "hrgbench/hw/rate_table.hpp"

namespace hrgbench::testing {

class RateTableWithoutAngle final : public hw::RateTable {
 public:
  explicit RateTableWithoutAngle(hw::RateTable& table) : table_(table) {}

  std::expected<void, hw::RateTableError> Connect() override { return table_.Connect(); }
  std::expected<void, hw::RateTableError> SetRate(double rate_rad_s) override {
    return table_.SetRate(rate_rad_s);
  }
  std::expected<void, hw::RateTableError> SetAccelerationLimit(double accel_rad_s2) override {
    return table_.SetAccelerationLimit(accel_rad_s2);
  }
  std::expected<hw::RateTableStatus, hw::RateTableError> ReadStatus() override {
    return table_.ReadStatus();
  }
  std::expected<hw::RateTableAngle, hw::RateTableError> ReadAngle() override {
    ++refused_angle_reads_;
    return std::unexpected(
        hw::RateTableError{hw::RateTableErrorCode::kNotSupported,
                           "test table speaks register map version 1, which has no encoder angle"});
  }
  std::expected<hw::RateTableStatus, hw::RateTableError> WaitUntilStable(
      const hw::StableCriteria& criteria) override {
    return table_.WaitUntilStable(criteria);
  }
  std::expected<void, hw::RateTableError> Heartbeat() override { return table_.Heartbeat(); }
  std::expected<void, hw::RateTableError> ResetFault() override { return table_.ResetFault(); }
  std::expected<void, hw::RateTableError> Stop() override { return table_.Stop(); }
  void SafeStop() noexcept override { table_.SafeStop(); }
  void Disconnect() noexcept override { table_.Disconnect(); }

  std::uint64_t refused_angle_reads() const noexcept { return refused_angle_reads_; }

 private:
  hw::RateTable& table_;
  std::uint64_t refused_angle_reads_ = 0;
};

}  // namespace hrgbench::testing
