// STYLE rule 3: the receive path does not allocate. A counting global operator new (this binary
// only) must not move while 100 000 samples stream through GyroCanDevice::ReadSamples, with the
// simulated electronics, the virtual bus and the decoder all running in this thread.
// Also measures the decode rate of the whole path (frames per second of wall time).

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <vector>

#include "allocation_counter.hpp"  // the counting operator new (this binary only)
#include "gyro_rig.hpp"

namespace hrgbench::testing {
namespace {

TEST(GyroReceiveAllocationTest, TheCounterSeesAllocations) {
  const std::int64_t before = hrgbench::testing::process_allocation_count.load();
  std::vector<int>* volatile escaped = new std::vector<int>(100);
  delete escaped;
  EXPECT_GE(hrgbench::testing::process_allocation_count.load() - before, 2);
}

TEST(GyroReceiveAllocationTest, StreamingOneHundredThousandSamplesDoesNotAllocate) {
  GyroRigOptions options;
  options.sim.sigma = 1e-4;
  options.bit_rate_bps = 0;  // untimed: measure the software path, not the simulated bus
  GyroRig rig(options);
  rig.StartRun(2000, {1.0, 0.2, 0.3});
  std::vector<hw::GyroSample> buffer(256);  // allocated before the loop
  std::size_t total = 0;
  std::uint32_t expected_seq = 0;
  bool in_order = true;

  const std::int64_t before = hrgbench::testing::process_allocation_count.load();
  const auto start = std::chrono::steady_clock::now();
  while (total < 100'000) {
    const hw::GyroReadResult r = rig.device->ReadSamples(buffer, 100'000'000);
    if (r.status != hw::GyroReadStatus::kOk) break;
    for (std::size_t i = 0; i < r.count; ++i)
      in_order = in_order && buffer[i].seq == expected_seq++;
    total += r.count;
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::int64_t allocations = hrgbench::testing::process_allocation_count.load() - before;

  EXPECT_GE(total, 100'000u);
  EXPECT_TRUE(in_order);
  EXPECT_EQ(allocations, 0) << "allocations on the receive path while streaming";
  EXPECT_EQ(rig.device->Counters().sequence_gaps, 0u);
  std::printf(
      "[ info ] %zu samples (%zu frames) through sim + virtual bus + GyroCanDevice in "
      "%.3f s: %.0f frames/s (classic CAN at 1 Mbit/s carries ~8 000 frames/s)\n",
      total, 2 * total, wall_s, 2.0 * static_cast<double>(total) / wall_s);
}

}  // namespace
}  // namespace hrgbench::testing
