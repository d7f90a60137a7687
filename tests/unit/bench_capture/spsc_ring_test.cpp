// SpscRing: single-threaded semantics (order, wrap-around, full/empty, overrun counting, spans),
// and a two-thread stress test: 10 million items (HRGBENCH_RING_STRESS_ITEMS; fewer in the
// ThreadSanitizer build, which is ~10x slower) pushed and popped concurrently in mixed single and
// span operations, through a small ring so that both full and empty are hit constantly; every
// item must arrive exactly once, in order, with its content intact. Prints the throughput.

#include "hrgbench/bench/capture/spsc_ring.hpp"

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <thread>
#include <vector>

#include "hrgbench/hw/gyro_electronics.hpp"

#ifndef HRGBENCH_RING_STRESS_ITEMS
#define HRGBENCH_RING_STRESS_ITEMS 10'000'000
#endif

namespace hrgbench::bench {
namespace {

TEST(SpscRingTest, CapacityMustBeAPowerOfTwo) {
  EXPECT_THROW(SpscRing<int>(0), std::invalid_argument);
  EXPECT_THROW(SpscRing<int>(1), std::invalid_argument);
  EXPECT_THROW(SpscRing<int>(3), std::invalid_argument);
  EXPECT_THROW(SpscRing<int>(1000), std::invalid_argument);
  EXPECT_EQ(SpscRing<int>(2).capacity(), 2u);
  EXPECT_EQ(SpscRing<int>(1024).capacity(), 1024u);
  static_assert(SpscRing<int>::IsValidCapacity(4096));
  static_assert(!SpscRing<int>::IsValidCapacity(4095));
}

TEST(SpscRingTest, IndicesLiveOnSeparateCacheLines) {
  // The layout promise of the header: the object is cache-line aligned and padded.
  EXPECT_EQ(alignof(SpscRing<int>) % kCacheLineBytes, 0u);
  EXPECT_GE(sizeof(SpscRing<int>), 3 * kCacheLineBytes);
}

TEST(SpscRingTest, SingleItemsComeOutInOrderAndAFullRingRefuses) {
  SpscRing<int> ring(4);
  int out = -1;
  EXPECT_FALSE(ring.TryPop(out));
  EXPECT_TRUE(ring.Empty());
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(ring.TryPush(i));
  EXPECT_EQ(ring.Size(), 4u);
  EXPECT_FALSE(ring.TryPush(99));  // full: refused, counted, nothing overwritten
  EXPECT_FALSE(ring.TryPush(98));
  EXPECT_EQ(ring.Overruns(), 2u);
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(ring.TryPop(out));
    EXPECT_EQ(out, i);
  }
  EXPECT_FALSE(ring.TryPop(out));
  EXPECT_EQ(ring.Pushed(), 4u);
  EXPECT_EQ(ring.Popped(), 4u);
}

TEST(SpscRingTest, SpansWrapAroundAndAPartialPushKeepsTheOldest) {
  SpscRing<std::uint32_t> ring(8);
  std::uint32_t next_in = 0;
  std::uint32_t next_out = 0;
  std::array<std::uint32_t, 5> in{};
  std::array<std::uint32_t, 5> out{};
  // 5 in, 5 out, 20 times: the window walks around the 8 slots, crossing the end every time.
  for (int round = 0; round < 20; ++round) {
    for (auto& v : in) v = next_in++;
    ASSERT_EQ(ring.Push(std::span<const std::uint32_t>(in)), 5u);
    ASSERT_EQ(ring.Pop(std::span<std::uint32_t>(out)), 5u);
    for (auto v : out) EXPECT_EQ(v, next_out++);
  }
  // 5 + 5 into 8 slots: the second push takes 3, refuses 2 (the newest).
  for (auto& v : in) v = next_in++;
  ASSERT_EQ(ring.Push(std::span<const std::uint32_t>(in)), 5u);
  for (auto& v : in) v = next_in++;
  ASSERT_EQ(ring.Push(std::span<const std::uint32_t>(in)), 3u);
  EXPECT_EQ(ring.Overruns(), 2u);
  std::array<std::uint32_t, 16> all{};
  ASSERT_EQ(ring.Pop(std::span<std::uint32_t>(all)), 8u);
  for (std::size_t i = 0; i < 8; ++i) EXPECT_EQ(all[i], 100u + i);
  EXPECT_EQ(ring.Pop(std::span<std::uint32_t>(all)), 0u);
  EXPECT_EQ(ring.Push(std::span<const std::uint32_t>()), 0u);
}

TEST(SpscRingTest, CarriesGyroSamplesUnchanged) {
  SpscRing<hw::GyroSample> ring(16);
  hw::GyroSample sample{7, -123456789012345, {1.5, -2.25, 3e-9, -4e9}};
  ASSERT_TRUE(ring.TryPush(sample));
  hw::GyroSample got;
  ASSERT_TRUE(ring.TryPop(got));
  EXPECT_EQ(got.seq, 7u);
  EXPECT_EQ(got.t_ns, sample.t_ns);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(got.y[k], sample.y[k]);
}

// An item whose content is a function of its index, so the consumer can check every byte.
struct StressItem {
  std::uint64_t index;
  std::uint64_t check;
  double value;
};
constexpr std::uint64_t CheckOf(std::uint64_t i) { return i * 0x9E3779B97F4A7C15ull ^ 0xA5A5u; }

TEST(SpscRingTest, TwoThreadsTenMillionItemsExactOrderAndContent) {
  constexpr std::uint64_t kItems = HRGBENCH_RING_STRESS_ITEMS;
  // Small on purpose: full and empty are hit all the time, the wrap-around every 1024 items.
  SpscRing<StressItem> ring(1024);

  std::thread producer([&ring] {
    std::array<StressItem, 37> batch{};  // odd size: batches straddle the wrap at every offset
    std::uint64_t i = 0;
    while (i < kItems) {
      if (i % 3 == 0) {  // mix single pushes and span pushes
        const StressItem item{i, CheckOf(i), static_cast<double>(i) * 0.5};
        if (ring.TryPush(item)) ++i;
        continue;
      }
      const std::size_t n =
          static_cast<std::size_t>(std::min<std::uint64_t>(batch.size(), kItems - i));
      for (std::size_t k = 0; k < n; ++k) {
        const std::uint64_t j = i + k;
        batch[k] = {j, CheckOf(j), static_cast<double>(j) * 0.5};
      }
      i += ring.Push(std::span<const StressItem>(batch.data(), n));  // the rest is re-offered
    }
  });

  const auto start = std::chrono::steady_clock::now();
  std::uint64_t expected = 0;
  std::uint64_t errors = 0;
  std::array<StressItem, 53> out{};
  while (expected < kItems) {
    std::size_t n = 0;
    if (expected % 5 == 0) {
      n = ring.TryPop(out[0]) ? 1 : 0;
    } else {
      n = ring.Pop(std::span<StressItem>(out));
    }
    for (std::size_t k = 0; k < n; ++k, ++expected) {
      const StressItem& item = out[k];
      if (item.index != expected || item.check != CheckOf(expected) ||
          item.value != static_cast<double>(expected) * 0.5) {
        ++errors;
      }
    }
  }
  producer.join();
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  EXPECT_EQ(errors, 0u);
  EXPECT_EQ(expected, kItems);
  EXPECT_EQ(ring.Pushed(), kItems);
  EXPECT_EQ(ring.Popped(), kItems);
  EXPECT_TRUE(ring.Empty());
  // The producer re-offers refused items, so "overruns" here counts full-ring refusals.
  std::printf(
      "[ info ] %llu items (24 B) through a 1024-slot ring, 2 threads: %.3f s, %.1f M "
      "items/s; %llu full-ring refusals\n",
      static_cast<unsigned long long>(kItems), wall_s, static_cast<double>(kItems) / wall_s * 1e-6,
      static_cast<unsigned long long>(ring.Overruns()));
}

TEST(SpscRingTest, ThroughputOfGyroSamplesInBatches) {
  // The capture's real pattern: batches of 64 GyroSamples (48 B) into a 64 Ki-sample ring.
  constexpr std::uint64_t kSamples = HRGBENCH_RING_STRESS_ITEMS;
  SpscRing<hw::GyroSample> ring(65536);
  std::thread producer([&ring] {
    std::array<hw::GyroSample, 64> batch{};
    std::uint64_t i = 0;
    while (i < kSamples) {
      const std::size_t n =
          static_cast<std::size_t>(std::min<std::uint64_t>(batch.size(), kSamples - i));
      for (std::size_t k = 0; k < n; ++k) batch[k].seq = static_cast<std::uint32_t>(i + k);
      i += ring.Push(std::span<const hw::GyroSample>(batch.data(), n));
    }
  });
  const auto start = std::chrono::steady_clock::now();
  std::vector<hw::GyroSample> out(4096);
  std::uint64_t received = 0;
  bool in_order = true;
  while (received < kSamples) {
    const std::size_t n = ring.Pop(std::span<hw::GyroSample>(out));
    for (std::size_t k = 0; k < n; ++k) {
      in_order = in_order && out[k].seq == static_cast<std::uint32_t>(received + k);
    }
    received += n;
  }
  producer.join();
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(in_order);
  std::printf(
      "[ info ] %llu GyroSamples (48 B) in batches of 64 through a 65536-slot ring, "
      "2 threads: %.3f s, %.1f M samples/s (%.2f GB/s)\n",
      static_cast<unsigned long long>(kSamples), wall_s,
      static_cast<double>(kSamples) / wall_s * 1e-6,
      static_cast<double>(kSamples) * sizeof(hw::GyroSample) / wall_s * 1e-9);
}

}  // namespace
}  // namespace hrgbench::bench
