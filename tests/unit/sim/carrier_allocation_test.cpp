// STYLE rule 3: the carrier chain's sample path does not allocate (it runs inside GyroSimNode's
// Service, under the virtual clock's lock). A counting global operator new (this binary only) must
// not move while CarrierSimulation::Release and 2000 output samples run, with Ω and the temperature
// changing every sample (so the transition and the pick-off's delay matrices are recomputed each
// time: the matrix exponential on fixed-size 4×4 matrices must not allocate either).

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "allocation_counter.hpp"  // the counting operator new (this binary only)
#include "sim/carrier_simulation.hpp"

namespace hrgbench::drivers::sim {
namespace {

TEST(CarrierAllocationTest, TheCounterSeesAllocations) {
  const std::int64_t before = hrgbench::testing::process_allocation_count.load();
  std::vector<int>* volatile escaped = new std::vector<int>(100);
  delete escaped;
  EXPECT_GE(hrgbench::testing::process_allocation_count.load() - before, 2);
}

TEST(CarrierAllocationTest, ReleaseAndSamplesDoNotAllocate) {
  CarrierOptions options;
  options.resonator.frequency_split_hz = 0.01;
  options.pickoff.errors = {0.98, 0.002, 0.001, 0.002};
  options.pickoff.common_delay_s = 2e-6;
  options.pickoff.white_noise_std = 1e-3;
  options.pickoff.coloured_noise_std = 1e-3;
  options.frequency_temperature_coefficient_per_c = 5e-5;
  options.electronics.reference.mode = ReferenceMode::kTracking;
  CarrierSimulation sim(options);  // construction may allocate; nothing after it
  const std::int64_t before = hrgbench::testing::process_allocation_count.load();
  sim.Release({{1.0, 0.1, 0.3, 0.0}, 0.3, 1000.0, 7, 25.0, 0.01});
  double sink = 0.0;
  for (int k = 0; k < 2000; ++k) sink += sim.Next(0.3 + 1e-9 * k)[0];
  EXPECT_EQ(hrgbench::testing::process_allocation_count.load() - before, 0);
  EXPECT_TRUE(std::isfinite(sink));
}

}  // namespace
}  // namespace hrgbench::drivers::sim
