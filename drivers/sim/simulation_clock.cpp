#include "sim/simulation_clock.hpp"

#include <algorithm>

namespace hrgbench::drivers::sim {

void SimulationClock::Advance(std::int64_t until_ns, bool wake_on_output) {
  if (serving_) {
    if (until_ns > NowNs()) now_ns_.store(until_ns, std::memory_order_release);
    return;
  }
  serving_ = true;
  for (;;) {
    const std::int64_t now = NowNs();
    SimulationParticipant* next = nullptr;
    std::int64_t next_ns = until_ns;
    for (SimulationParticipant* p : participants_) {
      const std::int64_t t = std::max(p->NextEventNs(), now);
      if (t <= next_ns && (next == nullptr || t < next_ns)) {
        next = p;
        next_ns = t;
      }
    }
    if (next == nullptr) break;
    now_ns_.store(next_ns, std::memory_order_release);
    if (next->Service(next_ns) && wake_on_output) {
      serving_ = false;
      return;
    }
  }
  if (until_ns > NowNs()) now_ns_.store(until_ns, std::memory_order_release);
  serving_ = false;
}

void SimulationClock::RemoveParticipant(SimulationParticipant* participant) {
  participants_.erase(std::remove(participants_.begin(), participants_.end(), participant),
                      participants_.end());
}

}  // namespace hrgbench::drivers::sim
