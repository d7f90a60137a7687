// Speed of the carrier-level simulated resonator and electronics (drivers/sim/carrier_simulation):
// a free run of the production length (100 s) at a 5 kHz carrier, converters at 100 kHz, output at
// 1 kHz, with converter noise and every anisotropy on (the default unit plus errors), one core.
// Google Benchmark; run by hand: build/bin/carrier_simulator_benchmark. The figure is in
// drivers/sim/README.md.

#include <benchmark/benchmark.h>

#include "sim/carrier_simulation.hpp"

namespace {

using hrgbench::drivers::sim::CarrierOptions;
using hrgbench::drivers::sim::CarrierRelease;
using hrgbench::drivers::sim::CarrierSimulation;
using hrgbench::drivers::sim::ReferenceMode;

CarrierOptions Unit(bool tracking) {
  CarrierOptions o;
  o.resonator.frequency_split_hz = 0.01;
  o.resonator.frequency_axis_rad = 0.3;
  o.resonator.damping_anisotropy_per_s = 1e-4;
  o.pickoff.errors = {1.01, 0.004, 0.002, 0.006};
  o.pickoff.common_delay_s = 2e-6;
  o.pickoff.white_noise_std = 1e-3;
  o.pickoff.coloured_noise_std = 1e-3;
  o.frequency_temperature_coefficient_per_c = 5e-5;
  o.electronics.reference.mode = tracking ? ReferenceMode::kTracking : ReferenceMode::kFreeRunning;
  return o;
}

// state.range(0): run length in s; state.range(1): 1 = tracking reference, 0 = free-running;
// state.range(2): 1 = temperature ramp (transition recomputed every output sample).
void BM_CarrierFreeRun(benchmark::State& state) {
  CarrierSimulation sim(Unit(state.range(1) != 0));
  const auto samples = static_cast<long>(state.range(0) * 1000);
  const double ramp = state.range(2) != 0 ? 0.01 : 0.0;
  for (auto _ : state) {
    sim.Release({{1.0, 0.0, 0.3, 0.0}, 1.0, 1000.0, 1, 25.0, ramp});
    double sink = 0.0;
    for (long k = 0; k < samples; ++k) sink += sim.Next(1.0)[0];
    benchmark::DoNotOptimize(sink);
  }
  state.counters["converter_samples_per_s"] =
      benchmark::Counter(static_cast<double>(samples) * sim.decimation(),
                         benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK(BM_CarrierFreeRun)
    ->Args({100, 0, 0})
    ->Args({100, 1, 0})
    ->Args({100, 1, 1})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(1.0);

}  // namespace

BENCHMARK_MAIN();
