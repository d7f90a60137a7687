#pragma once
// Time source for drivers, sequencers and simulated hardware. Production code uses SteadyClock;
// tests and faster-than-real-time simulation use ManualClock, which only moves when told to, so a
// timeout or a settle window can be tested without sleeping.
//
// Units: nanoseconds on a monotonic time base (not wall-clock time; never jumps).

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <thread>

namespace hrgbench::hw {

// Seconds (a config's, a plan's) as this base's nanoseconds, rounded to the nearest.
inline std::int64_t SecondsToNs(double seconds) noexcept {
  return static_cast<std::int64_t>(std::llround(seconds * 1e9));
}

class Clock {
 public:
  virtual ~Clock() = default;
  // Monotonic time in ns. Thread-safe, real-time safe (no allocation, no lock, no system call
  // beyond clock_gettime's vDSO).
  virtual std::int64_t NowNs() const noexcept = 0;
  // Blocks the calling thread for `duration_ns` of this clock's time. Not real-time safe. A
  // ManualClock returns once another thread has advanced it far enough.
  virtual void SleepForNs(std::int64_t duration_ns) = 0;
  // For simulated clocks that advance only when every thread using them waits
  // (drivers/sim_station's VirtualTimeClock): a new thread calls AttachCurrentThread() first thing,
  // so time does not run on while it starts, and DetachCurrentThread() before it ends or blocks
  // elsewhere for long. Real clocks ignore both. Not real-time safe (may take a lock).
  virtual void AttachCurrentThread() {}
  virtual void DetachCurrentThread() {}
};

class SteadyClock final : public Clock {
 public:
  std::int64_t NowNs() const noexcept override {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
  void SleepForNs(std::int64_t duration_ns) override {
    if (duration_ns > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(duration_ns));
  }
};

// A clock that moves only when Advance() or Set() is called. SleepForNs() advances it itself when
// `auto_advance` is true (single-threaded tests: a sleep is an instant jump), else it waits for
// another thread to advance it.
class ManualClock final : public Clock {
 public:
  explicit ManualClock(std::int64_t start_ns = 0, bool auto_advance = true)
      : now_ns_(start_ns), auto_advance_(auto_advance) {}
  std::int64_t NowNs() const noexcept override { return now_ns_.load(std::memory_order_acquire); }
  void SleepForNs(std::int64_t duration_ns) override {
    if (duration_ns <= 0) return;
    if (auto_advance_) {
      Advance(duration_ns);
      return;
    }
    const std::int64_t until = NowNs() + duration_ns;
    while (NowNs() < until) std::this_thread::yield();
  }
  void Advance(std::int64_t delta_ns) noexcept {
    now_ns_.fetch_add(delta_ns, std::memory_order_acq_rel);
  }
  void Set(std::int64_t now_ns) noexcept { now_ns_.store(now_ns, std::memory_order_release); }

 private:
  std::atomic<std::int64_t> now_ns_;
  bool auto_advance_;
};

}  // namespace hrgbench::hw
