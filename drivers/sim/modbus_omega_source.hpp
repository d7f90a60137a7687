#pragma once
// ModbusOmegaSource: Ω for the hrg-gyro-sim program, read from the rate table (or its simulator,
// hrg-table-sim) over Modbus TCP: the measured rate (input registers 4-5, float32, register map
// drivers/modbus_rate_table/README.md) plus a constant Earth-rate component. Read-only: it never
// writes the table (the bench's sequencer owns it, and its watchdog).
//
// A background thread polls every poll_period_ms with its own libmodbus context; OmegaRadS()
// returns the latest value (lock-free, real-time safe), so the sample loop never waits on Modbus.
// On a failed read the last value is kept, the failure counted, and the link reopened after a
// back-off.

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

namespace hrgbench::drivers::sim {

class ModbusOmegaSource {
 public:
  ModbusOmegaSource(std::string host, int port, double earth_rate_rad_s, int poll_period_ms);
  ~ModbusOmegaSource();  // stops and joins the thread
  ModbusOmegaSource(const ModbusOmegaSource&) = delete;
  ModbusOmegaSource& operator=(const ModbusOmegaSource&) = delete;

  double OmegaRadS() const noexcept { return omega_rad_s_.load(std::memory_order_acquire); }
  std::uint64_t reads() const noexcept { return reads_.load(std::memory_order_relaxed); }
  std::uint64_t failures() const noexcept { return failures_.load(std::memory_order_relaxed); }

 private:
  void Poll();

  const std::string host_;
  const int port_;
  const double earth_rate_rad_s_;
  const int poll_period_ms_;
  std::atomic<double> omega_rad_s_;
  std::atomic<std::uint64_t> reads_{0};
  std::atomic<std::uint64_t> failures_{0};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace hrgbench::drivers::sim
