#pragma once
// Runs the simulated table's Modbus server in a thread for a test, on a free TCP port of
// 127.0.0.1 (libmodbus cannot listen on port 0, so ports are tried from a per-process start in a
// range) or on a serial device. The physics object is reachable for assertions and for pressing
// the e-stop.

#include <unistd.h>

#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "hrgbench/hw/clock.hpp"
#include "modbus_rate_table/modbus_config.hpp"
#include "sim/modbus_table_server.hpp"
#include "sim/table_physics.hpp"

namespace hrgbench::testing {

inline drivers::sim::TablePhysicsOptions FastTable() {
  drivers::sim::TablePhysicsOptions o;
  o.max_accel_rad_s2 = 50.0;
  o.settle_time_constant_s = 0.02;
  o.noise_rad_s = 1e-5;
  o.stable_hold_s = 0.05;
  return o;
}

class SimTable {
 public:
  explicit SimTable(drivers::sim::TablePhysicsOptions physics = FastTable(),
                    drivers::sim::TableServerOptions server = {})
      : physics_(physics, clock_), server_options_(std::move(server)) {}
  ~SimTable() { Stop(); }

  // Opens the server (TCP: first free port from a per-process start) and runs it in a thread.
  // Empty string on success, else why.
  std::string Start() {
    std::string last_error;
    const bool tcp = server_options_.transport == drivers::sim::TableServerOptions::Transport::kTcp;
    const int first = 20000 + static_cast<int>(::getpid() % 2000) * 10;
    for (int i = 0; i < (tcp ? 100 : 1); ++i) {
      auto options = server_options_;
      if (tcp) options.port = 20000 + (first - 20000 + i * 7) % 40000;
      server_ = std::make_unique<drivers::sim::ModbusTableServer>(physics_, options);
      if (auto opened = server_->Open(); opened) {
        port_ = options.port;
        thread_ = std::thread([this] { server_->Run(); });
        return {};
      } else {
        last_error = opened.error();
      }
    }
    server_.reset();
    return last_error;
  }

  void Stop() {
    if (server_ == nullptr) return;
    server_->RequestStop();
    if (thread_.joinable()) thread_.join();
    server_.reset();  // closes the listening socket and every client connection
  }

  drivers::modbus_rate_table::ModbusRateTableConfig DriverConfig() const {
    drivers::modbus_rate_table::ModbusRateTableConfig c;
    c.host = "127.0.0.1";
    c.port = port_;
    c.response_timeout_ms = 200;
    c.accel_limit_rad_s2 = 2.0;
    return c;
  }

  drivers::sim::TablePhysics& physics() { return physics_; }
  drivers::sim::ModbusTableServer& server() { return *server_; }
  int port() const { return port_; }

 private:
  hw::SteadyClock clock_;
  drivers::sim::TablePhysics physics_;
  drivers::sim::TableServerOptions server_options_;
  std::unique_ptr<drivers::sim::ModbusTableServer> server_;
  std::thread thread_;
  int port_ = 0;
};

}  // namespace hrgbench::testing
