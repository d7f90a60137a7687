#pragma once
// Runs fn(i) for i in [0, n) on up to `threads` threads (the caller's included). Runs are
// independent in every estimator pass, so they are the unit of work. threads ≤ 1 runs inline and
// creates no thread, for targets without threads (the gyro's own electronics).
//
// Internal to the estimator library.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace hrgbench::estimator::internal {

// Resolves a requested thread count: 0 means "as many as the hardware has".
inline int ResolveThreads(int requested, std::size_t tasks) {
  int threads = requested > 0 ? requested : static_cast<int>(std::thread::hardware_concurrency());
  threads = std::max(1, threads);
  return static_cast<int>(
      std::min<std::size_t>(static_cast<std::size_t>(threads), std::max<std::size_t>(1, tasks)));
}

template <typename Fn>
void ParallelFor(std::size_t n, int threads, Fn fn) {
  if (threads <= 1 || n <= 1) {
    for (std::size_t i = 0; i < n; ++i) fn(i);
    return;
  }
  std::atomic<std::size_t> next{0};
  // The first exception a task throws (a run set's read error, std::bad_alloc) ends the loop and
  // is rethrown to the caller once every thread has stopped, as the inline loop would throw it.
  std::exception_ptr failure;
  std::mutex failure_mutex;
  const auto worker = [&] {
    try {
      for (std::size_t i = next.fetch_add(1); i < n; i = next.fetch_add(1)) fn(i);
    } catch (...) {
      next.store(n);
      const std::lock_guard<std::mutex> lock(failure_mutex);
      if (!failure) failure = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(static_cast<std::size_t>(threads - 1));
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& th : pool) th.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace hrgbench::estimator::internal
