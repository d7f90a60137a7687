#pragma once
// SimulationClock: a discrete-event clock for running simulated hardware faster than real time in
// ONE thread. It only moves when someone sleeps on it (or calls AdvanceTo); while it moves it
// stops at every event of its participants (e.g. a GyroSimNode's next sample) and lets them act at
// exactly that time. A driver under test that waits in CanBus::Receive on a VirtualCanBus using
// this clock thus "sleeps" while the simulated electronics answer and stream: 10 s of 1 kHz
// samples take a fraction of a second, deterministically.
//
// Threads: single-threaded by design (the test thread). Not real-time safe.

#include <atomic>
#include <cstdint>
#include <vector>

#include "hrgbench/hw/clock.hpp"

namespace hrgbench::drivers::sim {

class SimulationParticipant {
 public:
  virtual ~SimulationParticipant() = default;
  // The next time (ns) this participant must act; may be ≤ now (act at once).
  virtual std::int64_t NextEventNs() const noexcept = 0;
  // Acts at `now_ns` (the clock already reads now_ns). Must not sleep on the clock. Returns true
  // when it sent something a sleeper may be waiting for (a frame): SleepForNs then returns early.
  virtual bool Service(std::int64_t now_ns) noexcept = 0;
};

class SimulationClock final : public hw::Clock {
 public:
  explicit SimulationClock(std::int64_t start_ns = 0) : now_ns_(start_ns) {}

  std::int64_t NowNs() const noexcept override { return now_ns_.load(std::memory_order_acquire); }
  // Advances by up to `duration_ns`, serving every participant event on the way, and returns
  // early right after an event that produced output (a "wake-up", as a condition variable would
  // give a real-time waiter). Callers wait in loops that re-check their condition and deadline
  // (as VirtualCanEndpoint::Receive does), so an early return costs nothing and keeps simulated
  // reaction times realistic (an Ack is seen when it arrives, not at the end of the timeout).
  void SleepForNs(std::int64_t duration_ns) override { Advance(NowNs() + duration_ns, true); }
  // Advances to `until_ns`, serving every event on the way (no early return).
  void AdvanceTo(std::int64_t until_ns) { Advance(until_ns, false); }

  // Participants are not owned and must outlive the clock's use (or be removed).
  void AddParticipant(SimulationParticipant* participant) { participants_.push_back(participant); }
  void RemoveParticipant(SimulationParticipant* participant);

 private:
  void Advance(std::int64_t until_ns, bool wake_on_output);

  std::atomic<std::int64_t> now_ns_;
  std::vector<SimulationParticipant*> participants_;
  bool serving_ = false;  // a participant's Service that sleeps only moves time, no recursion
};

}  // namespace hrgbench::drivers::sim
