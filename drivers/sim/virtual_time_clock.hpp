#pragma once
// VirtualTimeClock: simulated time shared by SEVERAL threads, advanced as fast as the CPU allows
// (or paced at a chosen multiple of real time), for the in-process simulated station in CI.
//
// Why not SimulationClock (drivers/sim): that one is single-threaded: whoever sleeps moves time.
// The bench blocks in two threads at once (the sequencer in RateTable::WaitUntilStable, the
// capture thread in GyroElectronics::ReadSamples, perhaps a frame recorder), and time must not
// run ahead of a thread that is still working, or a capture thread would find its queue
// overflowed and a sequencer its table's watchdog expired.
//
// Design: a conservative discrete-event clock.
//   - A thread ATTACHES by its first wait (SleepForNs / WaitForOutput) and detaches when it exits
//     (or DetachCurrentThread); AttachCurrentThread attaches at once. NowNs() alone does not.
//   - Time advances only when every attached thread is waiting (but see output_lookahead_ns: a
//     thread woken by a frame lets time run on a little, so frames are handled in batches). Then
//     the last thread to wait
//     advances it to the earliest of: the waiters' deadlines and the participants' next events
//     (SimulationParticipant, e.g. GyroSimNode), serves the participants due at that instant
//     (under the clock's mutex, so they need no locking of their own), and wakes the waiters whose
//     deadline has come, or, for WaitForOutput waiters, when a participant produced output or a
//     thread called NotifyOutput (a frame was sent). Woken threads count as running at once, so
//     time cannot slip past them before they are scheduled.
//   - A thread that blocks on something other than this clock (join, a mutex, a condition
//     variable) would stall time for ever; after park_after_wall_ns of wall time without waiting
//     on the clock it is PARKED (counted in Statistics().parks) and time goes on without it until
//     its next wait, but only if the kernel says it is asleep: a thread that is runnable (working,
//     or starved of a CPU on a loaded machine) or in uninterruptible I/O (fsync) is not parked
//     (Statistics().park_deferrals) and time keeps waiting for it. Nor is a thread queueing for
//     this clock's own lock (asleep on its futex, it looks blocked): one woken inside a wait, or
//     any thread while another is entering the clock. So a loaded machine makes a simulation
//     slower, never different; parks happen around a join or a wait off the clock.
//   - Pacing (time_scale > 0): before each advance, wait until the wall clock catches up:
//     simulated elapsed = time_scale × wall elapsed, counted from the first advance. A simulation
//     that falls behind (a loaded machine, threads working off the clock) makes up at most 20 ms
//     of wall time, then goes on from where it is rather than running fast to catch up.
//     time_scale = 0: as fast as possible.
//
// Contract for users: in faster-than-real-time mode every timed wait must be on this clock
// (SleepForNs, or a driver call that waits on it); a std::this_thread::sleep_for or a condition
// variable with a timeout measures wall time, which here is meaningless.
//
// Limits: one mutex serialises every wait and every participant service (fine for a handful of
// threads); participants must not wait on this clock or call NotifyOutput from Service; a thread
// that never waits on the clock and never detaches, while busy for ever (a spin loop), holds
// time back for ever; the park check reads /proc/self/task/<tid>/stat (Linux; elsewhere every
// thread past park_after_wall_ns is parked).
//
// Threads: every method from any thread. NowNs() is real-time safe (an atomic load); the waits
// are not (mutex, condition variable; the first wait of a thread allocates its record).

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "hrgbench/hw/clock.hpp"
#include "sim/simulation_clock.hpp"

namespace hrgbench::drivers::sim_station {

struct VirtualTimeClockOptions {
  std::int64_t start_ns = 0;
  // Simulated seconds per wall-clock second; 0 = as fast as possible.
  double time_scale = 0.0;
  // A thread not waiting on the clock for this long (wall time) while the others wait is parked.
  // 200 ms is far above the microseconds a capture loop spends between waits, and short enough
  // that a join costs little.
  std::int64_t park_after_wall_ns = 200'000'000;
  // A thread woken by OUTPUT (a frame for it) lets time run on this far before time waits for it
  // again: without it every frame costs two thread switches (a 3-thread bench capturing 600 s
  // at 1 kHz took 34 s of wall time; with 20 ms, a few). Invisible to the data: frames carry
  // their bus time stamps, and queues hold far more than 20 ms. What it changes: such a thread
  // may see NowNs() up to this much later than the frame that woke it, so its next deadline and
  // its reply (e.g. a command after the last sample) are late by as much. Deadline wake-ups
  // (sleeps, timeouts) are exact. 0: strictly conservative.
  std::int64_t output_lookahead_ns = 20'000'000;

  bool IsValid(std::string* why) const;
};

struct VirtualTimeClockStatistics {
  std::uint64_t advances = 0;          // time jumps
  std::uint64_t services = 0;          // participant Service calls
  std::uint64_t outputs = 0;           // output notifications (participant output or NotifyOutput)
  std::uint64_t parks = 0;             // threads parked after park_after_wall_ns
  std::uint64_t park_deferrals = 0;    // park checks that found the thread working, not blocked
  std::uint64_t attached_threads = 0;  // threads attached now
};

class VirtualTimeClock final : public hw::Clock {
 public:
  explicit VirtualTimeClock(const VirtualTimeClockOptions& options = {});
  ~VirtualTimeClock() override;
  VirtualTimeClock(const VirtualTimeClock&) = delete;
  VirtualTimeClock& operator=(const VirtualTimeClock&) = delete;

  std::int64_t NowNs() const noexcept override;
  // Returns once the clock has advanced by `duration_ns` (at once for <= 0).
  void SleepForNs(std::int64_t duration_ns) override;
  // Returns once the clock reaches `deadline_ns` OR OutputEpoch() differs from `seen_epoch`
  // (read it before checking for output, so nothing is missed). For receivers of frames.
  void WaitForOutput(std::int64_t deadline_ns, std::uint64_t seen_epoch);
  std::uint64_t OutputEpoch() const noexcept;
  // Something a WaitForOutput waiter may want was produced (a frame sent): wake them.
  void NotifyOutput();

  // Participants are not owned; they are served under the clock's mutex. Remove before
  // destroying them.
  void AddParticipant(sim::SimulationParticipant* participant);
  void RemoveParticipant(sim::SimulationParticipant* participant);
  // Runs `f` under the clock's mutex: the participants are not being served meanwhile (e.g. to
  // change a GyroSimNode's faults from a test).
  void WithParticipantsLocked(const std::function<void()>& f);

  // Holds time back for the calling thread from now on, as its first wait would. A thread is
  // otherwise unknown until it first waits: time may move on while a new thread starts (as a
  // slow-starting thread on real hardware would find; frames wait in the queues). Call it first
  // thing in a thread whose first moments matter.
  void AttachCurrentThread() override;
  // The calling thread no longer holds time back (until its next wait).
  void DetachCurrentThread() override;

  VirtualTimeClockStatistics Statistics() const;
  const VirtualTimeClockOptions& options() const noexcept { return options_; }

  struct Core;  // shared with the per-thread records, so a thread may outlive the clock

 private:
  void Wait(std::int64_t deadline_ns, bool wake_on_output, std::uint64_t seen_epoch);

  VirtualTimeClockOptions options_;
  std::shared_ptr<Core> core_;
};

}  // namespace hrgbench::drivers::sim_station
