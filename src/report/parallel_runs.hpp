#pragma once
// Runs fn(i) for i = 0 … n−1 on up to hardware_concurrency threads (the caller's included): the
// report's per-run work (fitted model, orbit elements, decimation) is independent between runs.
// fn must not throw. Internal to src/report.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace hrgbench::report::internal {

template <typename Fn>
void ParallelRuns(std::size_t n, Fn fn) {
  const std::size_t threads =
      std::min<std::size_t>(n, std::max(1u, std::thread::hardware_concurrency()));
  std::atomic<std::size_t> next{0};
  const auto work = [&]() {
    for (std::size_t i = next.fetch_add(1); i < n; i = next.fetch_add(1)) fn(i);
  };
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
}

}  // namespace hrgbench::report::internal
