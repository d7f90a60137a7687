// One status read (FC 04, 11 registers) = one Modbus TCP round trip on 127.0.0.1, through the real
// driver and the simulated table's server. Run with --benchmark_repetitions=10 for a median.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <memory>
#include <thread>

#include "modbus_rate_table/modbus_rate_table.hpp"
#include "sim/modbus_table_server.hpp"

namespace {
using namespace hrgbench;

void BM_ReadStatusRoundTrip(benchmark::State& state) {
  hw::SteadyClock clock;
  drivers::sim::TablePhysics physics({}, clock);
  std::unique_ptr<drivers::sim::ModbusTableServer> server;
  int port = 0;
  for (int i = 0; i < 100 && server == nullptr; ++i) {
    drivers::sim::TableServerOptions options;
    options.port = 30000 + static_cast<int>(::getpid() % 1000) * 10 + i;
    auto candidate = std::make_unique<drivers::sim::ModbusTableServer>(physics, options);
    if (candidate->Open()) {
      server = std::move(candidate);
      port = options.port;
    }
  }
  if (server == nullptr) {
    state.SkipWithError("no free port for the simulator");
    return;
  }
  std::thread serving([&] { server->Run(); });
  drivers::modbus_rate_table::ModbusRateTableConfig config;
  config.port = port;
  drivers::modbus_rate_table::ModbusRateTable table(config, clock);
  if (!table.Connect()) {
    state.SkipWithError("connect failed");
  } else {
    for (auto _ : state) {
      auto status = table.ReadStatus();
      if (!status) {
        state.SkipWithError(status.error().ToString().c_str());
        break;
      }
      benchmark::DoNotOptimize(status->measured_rate_rad_s);
    }
    state.counters["heartbeats"] = static_cast<double>(table.counters().heartbeats);
  }
  table.Disconnect();
  server->RequestStop();
  serving.join();
}
BENCHMARK(BM_ReadStatusRoundTrip)->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
