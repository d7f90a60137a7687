// hrg-gyro-sim: the simulated HRG electronics as a CAN node (protocol v2,
// drivers/gyro_can/README.md) on a SocketCAN interface, so the real GyroCanDevice can be tested
// against it as a separate process (in the QEMU kernel harness on vcan0, or on a bench's second CAN
// adapter). Runs until SIGINT/SIGTERM.
//
//   hrg-gyro-sim --can vcan0 --config drivers/sim/gyro_sim.example.toml
//   hrg-gyro-sim --can vcan0 --omega-rad-s 0.3            (defaults for everything else)
//   hrg-gyro-sim --can vcan0 --config sim.toml --table 127.0.0.1:1502   (Ω from hrg-table-sim)

#include <CLI/CLI.hpp>
#include <atomic>
#include <csignal>
#include <iostream>
#include <memory>
#include <optional>
#include <thread>

#include "hrgbench/hw/clock.hpp"
#include "sim/gyro_sim_config.hpp"
#include "sim/gyro_sim_node.hpp"
#include "sim/host_port.hpp"
#include "sim/modbus_omega_source.hpp"
#ifdef HRGBENCH_HAVE_SOCKETCAN
#include "socketcan/socket_can_bus.hpp"
#endif

namespace {

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop.store(true); }

}  // namespace

int main(int argc, char** argv) {
  using namespace hrgbench;
  try {
    CLI::App app{"Simulated HRG electronics on a CAN interface (hrg_gyro_v2 protocol)"};
    std::string interface_name, config_path, table;
    std::optional<double> omega_override;
    app.add_option("--can", interface_name, "SocketCAN interface, e.g. vcan0")->required();
    app.add_option("--config", config_path, "TOML config (drivers/sim/gyro_sim.example.toml)");
    std::optional<int> node_id;
    app.add_option("--node", node_id,
                   "Node id on the bus, 0..15 (overrides [electronics] node; several units on "
                   "one bus need distinct ones)")
        ->check(CLI::Range(0, static_cast<int>(drivers::gyro_can::kMaxNodeId)));
    app.add_option("--omega-rad-s", omega_override, "Constant Omega, rad/s (overrides [omega])");
    app.add_option("--table", table, "Read Omega from a Modbus rate table at HOST:PORT");
    CLI11_PARSE(app, argc, argv);

    drivers::sim::GyroSimFileConfig config;
    if (!config_path.empty()) {
      auto loaded = drivers::sim::LoadGyroSimConfig(config_path);
      if (!loaded) {
        std::cerr << "hrg-gyro-sim: " << loaded.error().ToString() << "\n";
        return 2;
      }
      config = *loaded;
    }
    if (!table.empty()) {
      const auto address = drivers::sim::ParseHostPort(table);
      if (!address) {
        std::cerr << "hrg-gyro-sim: --table wants HOST:PORT, got '" << table << "'\n";
        return 2;
      }
      config.omega.modbus_host = address->host;
      config.omega.modbus_port = address->port;
      config.omega.source = drivers::sim::OmegaConfig::Source::kModbus;
    }
    if (node_id) config.options.node = static_cast<drivers::gyro_can::NodeId>(*node_id);
    if (omega_override) {
      config.omega.source = drivers::sim::OmegaConfig::Source::kConstant;
      config.omega.omega_rad_s = *omega_override;
    }

#ifdef HRGBENCH_HAVE_SOCKETCAN
    auto bus = drivers::socketcan::SocketCanBus::Open(interface_name, {});
    if (!bus) {
      std::cerr << "hrg-gyro-sim: " << bus.error() << "\n";
      return 1;
    }
    std::unique_ptr<drivers::sim::ModbusOmegaSource> modbus;
    drivers::sim::OmegaSource omega;
    if (config.omega.source == drivers::sim::OmegaConfig::Source::kModbus) {
      modbus = std::make_unique<drivers::sim::ModbusOmegaSource>(
          config.omega.modbus_host, config.omega.modbus_port, config.omega.earth_rate_rad_s,
          config.omega.poll_period_ms);
      omega = [source = modbus.get()] { return source->OmegaRadS(); };
    } else {
      omega = [w = config.omega.omega_rad_s] { return w; };
    }
    hw::SteadyClock clock;
    drivers::sim::GyroSimNode node(**bus, clock, config.options, omega);
    std::signal(SIGINT, OnSignal);
    std::signal(SIGTERM, OnSignal);
    std::cout << "hrg-gyro-sim: node " << static_cast<int>(config.options.node) << " on "
              << interface_name << (bus.value()->SupportsFd() ? " (FD)" : "") << ", omega from "
              << (modbus ? "modbus " + config.omega.modbus_host + ":" +
                               std::to_string(config.omega.modbus_port)
                         : "constant " + std::to_string(config.omega.omega_rad_s) + " rad/s")
              << std::endl;
    node.Run(g_stop);
    const drivers::sim::GyroSimStatistics s = node.Statistics();
    std::cout << "hrg-gyro-sim: " << s.commands << " commands, " << s.runs << " runs, " << s.samples
              << " samples, " << s.frames_sent << " frames sent, " << s.send_failures
              << " send failures" << std::endl;
    return 0;
#else
    std::cerr << "hrg-gyro-sim: built without the SocketCAN transport (drivers/socketcan)\n";
    return 1;
#endif
  } catch (const std::exception& e) {
    std::cerr << "hrg-gyro-sim: " << e.what() << "\n";
    return 1;
  }
}
