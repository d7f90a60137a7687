#include "sim/modbus_omega_source.hpp"

#include <modbus/modbus.h>

#include <chrono>

#include "modbus_rate_table/register_map.hpp"

namespace hrgbench::drivers::sim {

ModbusOmegaSource::ModbusOmegaSource(std::string host, int port, double earth_rate_rad_s,
                                     int poll_period_ms)
    : host_(std::move(host)),
      port_(port),
      earth_rate_rad_s_(earth_rate_rad_s),
      poll_period_ms_(poll_period_ms),
      omega_rad_s_(earth_rate_rad_s),
      thread_([this] { Poll(); }) {}

ModbusOmegaSource::~ModbusOmegaSource() {
  stop_.store(true, std::memory_order_release);
  thread_.join();
}

void ModbusOmegaSource::Poll() {
  modbus_t* ctx = nullptr;
  const auto sleep_ms = [this](int ms) {
    for (int waited = 0; waited < ms && !stop_.load(std::memory_order_acquire); waited += 10) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  };
  while (!stop_.load(std::memory_order_acquire)) {
    if (ctx == nullptr) {
      ctx = modbus_new_tcp(host_.c_str(), port_);
      if (ctx != nullptr) modbus_set_response_timeout(ctx, 0, 200'000);
      if (ctx == nullptr || modbus_connect(ctx) != 0) {
        if (ctx != nullptr) modbus_free(ctx);
        ctx = nullptr;
        failures_.fetch_add(1, std::memory_order_relaxed);
        sleep_ms(500);
        continue;
      }
    }
    std::uint16_t regs[2] = {0, 0};
    if (modbus_read_input_registers(ctx, modbus_rate_table::input::kMeasuredRate, 2, regs) == 2) {
      const double rate = modbus_rate_table::DecodeFloat32(regs[0], regs[1]);
      omega_rad_s_.store(rate + earth_rate_rad_s_, std::memory_order_release);
      reads_.fetch_add(1, std::memory_order_relaxed);
    } else {
      failures_.fetch_add(1, std::memory_order_relaxed);
      modbus_close(ctx);
      modbus_free(ctx);
      ctx = nullptr;
      sleep_ms(500);
      continue;
    }
    sleep_ms(poll_period_ms_);
  }
  if (ctx != nullptr) {
    modbus_close(ctx);
    modbus_free(ctx);
  }
}

}  // namespace hrgbench::drivers::sim
