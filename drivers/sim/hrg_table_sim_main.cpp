// hrg-table-sim: the simulated rate table as a Modbus TCP or RTU server (README in
// drivers/modbus_rate_table/ documents the register map). Runs until SIGINT/SIGTERM.
//
//   hrg-table-sim --tcp 127.0.0.1:1502
//   hrg-table-sim --rtu /dev/pts/3 --baud 115200 --unit-id 1 --fault-at input:4=late*1

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <thread>

#include "sim/host_port.hpp"
#include "sim/modbus_table_server.hpp"

namespace {
using hrgbench::drivers::sim::TableServerOptions;

}  // namespace

int main(int argc, char** argv) {
  try {
    CLI::App app{"Simulated rate table speaking the hrgbench Modbus register map"};
    std::string tcp, rtu;
    TableServerOptions server;
    hrgbench::drivers::sim::TablePhysicsOptions physics;
    std::vector<std::string> fault_texts;
    double estop_after_s = -1.0;
    auto* tcp_opt = app.add_option("--tcp", tcp, "Listen on HOST:PORT (e.g. 127.0.0.1:1502)");
    app.add_option("--rtu", rtu, "Serve RTU on this serial device (e.g. /dev/pts/3)")
        ->excludes(tcp_opt);
    app.add_option("--baud", server.baud, "RTU baud rate")->capture_default_str();
    app.add_option("--parity", server.parity, "RTU parity N, E or O")->capture_default_str();
    app.add_option("--unit-id", server.unit_id, "Modbus unit id")->capture_default_str();
    app.add_option("--late-reply-ms", server.late_reply_ms, "Delay of 'late' faults")
        ->capture_default_str();
    app.add_option("--fault-at", fault_texts,
                   "Fault rule holding|input:<addr>=exception|late|wrong-length[*n] (repeatable)");
    app.add_option("--max-rate", physics.max_rate_rad_s, "Hardware rate limit, rad/s")
        ->capture_default_str();
    app.add_option("--accel-limit", physics.accel_limit_rad_s2, "Power-on accel limit, rad/s^2")
        ->capture_default_str();
    app.add_option("--max-accel", physics.max_accel_rad_s2, "Settable accel ceiling, rad/s^2")
        ->capture_default_str();
    app.add_option("--tau", physics.settle_time_constant_s, "Rate-loop time constant, s")
        ->capture_default_str();
    app.add_option("--noise", physics.noise_rad_s, "Measured-rate noise (1 sigma), rad/s")
        ->capture_default_str();
    app.add_option("--seed", physics.seed, "Noise seed")->capture_default_str();
    app.add_option("--encoder-counts", physics.encoder_counts_per_rev,
                   "Encoder counts per revolution (1..2^32-1)")
        ->capture_default_str();
    app.add_option("--encoder-noise", physics.encoder_noise_rad,
                   "Encoder read noise (1 sigma, before quantisation), rad")
        ->capture_default_str();
    app.add_option("--map-version", server.map_version,
                   "Register map version served: 2, or 1 (no encoder angle)")
        ->check(CLI::Range(1, 2))
        ->capture_default_str();
    app.add_option("--watchdog-ms", physics.watchdog_ms, "Power-on watchdog timeout, ms")
        ->capture_default_str();
    app.add_option("--estop-after-s", estop_after_s, "Press the e-stop this long after start");
    app.add_flag("--debug", server.debug, "Dump Modbus frames (libmodbus debug)");
    CLI11_PARSE(app, argc, argv);

    if (!rtu.empty()) {
      server.transport = TableServerOptions::Transport::kRtu;
      server.serial_device = rtu;
    } else if (const auto address =
                   hrgbench::drivers::sim::ParseHostPort(tcp.empty() ? "127.0.0.1:1502" : tcp)) {
      server.host = address->host;
      server.port = address->port;
    } else {
      std::cerr << "hrg-table-sim: --tcp wants HOST:PORT, got '" << tcp << "'\n";
      return 2;
    }
    if (std::string why; !physics.IsValid(&why)) {
      std::cerr << "hrg-table-sim: " << why << "\n";
      return 2;
    }
    hrgbench::hw::SteadyClock clock;
    hrgbench::drivers::sim::TablePhysics table(physics, clock);
    hrgbench::drivers::sim::ModbusTableServer modbus(table, server);
    for (const auto& text : fault_texts) {
      auto rule = hrgbench::drivers::sim::ParseFaultRule(text);
      if (!rule) {
        std::cerr << "hrg-table-sim: " << rule.error() << "\n";
        return 2;
      }
      modbus.AddFault(*rule);
    }
    if (auto opened = modbus.Open(); !opened) {
      std::cerr << "hrg-table-sim: " << opened.error() << "\n";
      return 1;
    }
    // Signals go to this thread only (sigtimedwait below); the server runs in its own.
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);
    std::expected<void, std::string> result;
    std::thread serving([&] { result = modbus.Run(); });
    std::cout << "hrg-table-sim: serving "
              << (rtu.empty() ? "tcp " + server.host + ":" + std::to_string(server.port)
                              : "rtu " + rtu)
              << " unit " << server.unit_id << std::endl;
    const auto start = std::chrono::steady_clock::now();
    bool estop_done = estop_after_s < 0.0;
    while (true) {
      timespec wait{0, 100'000'000};
      if (sigtimedwait(&signals, nullptr, &wait) > 0) break;
      if (!estop_done && std::chrono::steady_clock::now() - start >=
                             std::chrono::duration<double>(estop_after_s)) {
        table.SetEStop(true);
        estop_done = true;
        std::cout << "hrg-table-sim: e-stop pressed" << std::endl;
      }
    }
    modbus.RequestStop();
    serving.join();
    if (!result) {
      std::cerr << "hrg-table-sim: " << result.error() << "\n";
      return 1;
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "hrg-table-sim: " << e.what() << "\n";
    return 1;
  }
}
