// VirtualTimeClock: simulated time shared by several threads. Time moves only when every attached
// thread waits, participants are served at their events, WaitForOutput wakes on output, a thread
// blocked elsewhere is parked, an exiting thread detaches, pacing follows the wall clock.

#include "sim/virtual_time_clock.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <future>
#include <latch>
#include <mutex>
#include <thread>
#include <vector>

namespace hrgbench::drivers::sim_station {
namespace {

constexpr std::int64_t kMs = 1'000'000;

double WallSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Fires every period_ns; output on every event.
class Ticker final : public sim::SimulationParticipant {
 public:
  explicit Ticker(std::int64_t period_ns) : period_ns_(period_ns), next_ns_(period_ns) {}
  std::int64_t NextEventNs() const noexcept override { return next_ns_; }
  bool Service(std::int64_t now_ns) noexcept override {
    served_at.push_back(now_ns);
    next_ns_ = now_ns + period_ns_;
    return true;
  }
  std::vector<std::int64_t> served_at;

 private:
  std::int64_t period_ns_;
  std::int64_t next_ns_;
};

TEST(VirtualTimeClockTest, OneThreadSleepsAreExactJumps) {
  VirtualTimeClock clock;
  for (int i = 0; i < 1000; ++i) clock.SleepForNs(100 * kMs);
  EXPECT_EQ(clock.NowNs(), 100'000 * kMs);
  EXPECT_EQ(clock.Statistics().advances, 1000u);
  clock.SleepForNs(0);
  clock.SleepForNs(-5);
  EXPECT_EQ(clock.NowNs(), 100'000 * kMs);
}

TEST(VirtualTimeClockTest, TwoThreadsWakeInSimulatedTimeOrder) {
  VirtualTimeClock clock;
  std::mutex mutex;
  std::vector<std::pair<std::int64_t, char>> wakes;
  std::latch attached(2);  // both hold time back before either sleeps
  const auto sleeper = [&](char name, std::int64_t period_ns, int count) {
    clock.AttachCurrentThread();
    attached.arrive_and_wait();
    for (int i = 0; i < count; ++i) {
      clock.SleepForNs(period_ns);
      std::lock_guard lock(mutex);
      wakes.emplace_back(clock.NowNs(), name);
    }
  };
  std::thread a(sleeper, 'a', 100 * kMs, 10);
  std::thread b(sleeper, 'b', 350 * kMs, 3);
  a.join();
  b.join();
  ASSERT_EQ(wakes.size(), 13u);
  for (std::size_t i = 1; i < wakes.size(); ++i) EXPECT_LE(wakes[i - 1].first, wakes[i].first);
  for (const auto& [t, name] : wakes) {
    EXPECT_EQ(t % (name == 'a' ? 100 * kMs : 350 * kMs), 0) << name << " woke at " << t;
  }
  EXPECT_EQ(clock.NowNs(), 1050 * kMs);
  EXPECT_EQ(clock.Statistics().attached_threads, 0u);  // both detached when they exited
  EXPECT_EQ(clock.Statistics().parks, 0u);
}

// Thread a does `work` off the clock between two sleeps while thread b's sleep falls due in the
// middle of it. True when b woke while a was still working: time did not wait for a.
bool TimeRanPastAWorkingThread(VirtualTimeClock& clock, const std::function<void()>& work) {
  std::atomic<bool> a_busy{false};
  std::atomic<bool> b_saw_a_busy{false};
  std::latch attached(2);
  std::thread a([&] {
    clock.AttachCurrentThread();
    attached.arrive_and_wait();
    clock.SleepForNs(1 * kMs);
    a_busy = true;
    work();
    a_busy = false;
    clock.SleepForNs(10 * kMs);
  });
  std::thread b([&] {
    clock.AttachCurrentThread();
    attached.arrive_and_wait();
    clock.SleepForNs(2 * kMs);  // due while a works: must wait for it
    b_saw_a_busy = a_busy.load();
  });
  a.join();
  b.join();
  return b_saw_a_busy;
}

TEST(VirtualTimeClockTest, TimeWaitsForABusyThread) {
  VirtualTimeClock clock;
  // Working, off the clock, for 30 ms of wall time (below the park time).
  EXPECT_FALSE(TimeRanPastAWorkingThread(
      clock, [] { std::this_thread::sleep_for(std::chrono::milliseconds(30)); }));
  EXPECT_EQ(clock.Statistics().parks, 0u);
}

TEST(VirtualTimeClockTest, AThreadBlockedElsewhereIsParked) {
  VirtualTimeClockOptions options;
  options.park_after_wall_ns = 50 * kMs;
  VirtualTimeClock clock(options);
  clock.SleepForNs(1 * kMs);  // the main thread is attached now
  std::thread worker([&] { clock.SleepForNs(10'000 * kMs); });
  worker.join();  // blocked off the clock: parked after 50 ms
  EXPECT_EQ(clock.NowNs(), 10'001 * kMs);
  EXPECT_EQ(clock.Statistics().parks, 1u);
  clock.DetachCurrentThread();
  EXPECT_EQ(clock.Statistics().attached_threads, 0u);
}

// A thread that works off the clock for longer than park_after_wall_ns (here: spins, as a thread
// starved of a CPU on a loaded machine would look) is not parked: time waits for it. Parking it
// let the simulated table's watchdog expire under load while the sequencer was merely slow.
TEST(VirtualTimeClockTest, AWorkingThreadIsNotParkedPastTheParkTime) {
  VirtualTimeClockOptions options;
  options.park_after_wall_ns = 20 * kMs;
  VirtualTimeClock clock(options);
  // Runnable for 10 park periods, never asleep.
  EXPECT_FALSE(TimeRanPastAWorkingThread(clock, [] {
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(200);
    while (std::chrono::steady_clock::now() < until) {
    }
  }));
  EXPECT_EQ(clock.Statistics().parks, 0u);
  EXPECT_GE(clock.Statistics().park_deferrals, 1u);
}

TEST(VirtualTimeClockTest, ParticipantsAreServedAtTheirEventsAndWakeOutputWaiters) {
  VirtualTimeClock clock;
  Ticker ticker(1 * kMs);
  clock.AddParticipant(&ticker);
  const std::uint64_t epoch = clock.OutputEpoch();
  clock.WaitForOutput(100 * kMs, epoch);  // woken by the first tick, not at the deadline
  EXPECT_EQ(clock.NowNs(), 1 * kMs);
  clock.SleepForNs(10 * kMs);  // a plain sleep is not woken by output
  EXPECT_EQ(clock.NowNs(), 11 * kMs);
  ASSERT_EQ(ticker.served_at.size(), 11u);
  for (std::size_t i = 0; i < ticker.served_at.size(); ++i) {
    EXPECT_EQ(ticker.served_at[i], static_cast<std::int64_t>(i + 1) * kMs);
  }
  clock.RemoveParticipant(&ticker);
  clock.SleepForNs(10 * kMs);
  EXPECT_EQ(ticker.served_at.size(), 11u);
}

TEST(VirtualTimeClockTest, NotifyOutputWakesAnotherThreadsWait) {
  VirtualTimeClock clock;
  clock.AttachCurrentThread();  // time must wait for this thread's NotifyOutput
  std::promise<void> waiting;
  std::int64_t woke_at = -1;
  std::thread receiver([&] {
    const std::uint64_t epoch = clock.OutputEpoch();
    waiting.set_value();
    clock.WaitForOutput(1'000 * kMs, epoch);
    woke_at = clock.NowNs();
  });
  waiting.get_future().wait();
  clock.SleepForNs(5 * kMs);
  clock.NotifyOutput();
  receiver.join();
  EXPECT_EQ(woke_at, 5 * kMs);
}

TEST(VirtualTimeClockTest, PacedTimeFollowsTheWallClock) {
  VirtualTimeClockOptions options;
  options.time_scale = 10.0;  // 10 simulated s per wall s
  VirtualTimeClock clock(options);
  const auto wall = std::chrono::steady_clock::now();
  clock.SleepForNs(1'000 * kMs);
  // Never faster than its scale (a loaded machine can only make it slower; speed is not judged).
  EXPECT_GE(WallSince(wall), 0.095);
}

// Pacing counts from the first advance and never makes up lost time: a clock that sat idle
// after it was built (a station being set up) or fell behind does not then run fast.
TEST(VirtualTimeClockTest, PacedTimeNeverRunsAheadOfItsScale) {
  VirtualTimeClockOptions options;
  options.time_scale = 10.0;
  VirtualTimeClock clock(options);
  std::this_thread::sleep_for(std::chrono::milliseconds(150));  // idle: 1.5 s "owed"
  auto wall = std::chrono::steady_clock::now();
  clock.SleepForNs(1'000 * kMs);
  EXPECT_GE(WallSince(wall), 0.095);
  std::this_thread::sleep_for(std::chrono::milliseconds(150));  // behind again
  wall = std::chrono::steady_clock::now();
  clock.SleepForNs(500 * kMs);  // 50 ms at scale, of which up to 20 ms may be made up
  EXPECT_GE(WallSince(wall), 0.025);
}

TEST(VirtualTimeClockTest, OptionsAreValidated) {
  std::string why;
  VirtualTimeClockOptions options;
  EXPECT_TRUE(options.IsValid(&why));
  options.time_scale = -1.0;
  EXPECT_FALSE(options.IsValid(&why));
  EXPECT_NE(why.find("time_scale"), std::string::npos);
}

}  // namespace
}  // namespace hrgbench::drivers::sim_station
