#include "sim/clocked_can_endpoint.hpp"

#include <algorithm>

namespace hrgbench::drivers::sim_station {

hw::CanStatus ClockedCanEndpoint::Send(const hw::CanFrame& frame,
                                       std::int64_t timeout_ns) noexcept {
  const hw::CanStatus status = endpoint_.Send(frame, timeout_ns);
  if (status == hw::CanStatus::kOk) {
    try {
      clock_.NotifyOutput();
    } catch (...) {
      // std::system_error from the mutex: the frame is on the bus; a waiter sees it at its
      // deadline at the latest.
    }
  }
  return status;
}

hw::CanStatus ClockedCanEndpoint::Receive(hw::CanFrame* frame, std::int64_t timeout_ns,
                                          hw::ReceiveInfo* info) noexcept {
  if (frame == nullptr) return hw::CanStatus::kInvalidArgument;
  const std::int64_t deadline_ns = clock_.NowNs() + std::max<std::int64_t>(timeout_ns, 0);
  // The endpoint's contract: bus-off on entry waits out the timeout, bus-off during it returns.
  const bool bus_off_on_entry = endpoint_.State() == hw::CanBusState::kBusOff;
  for (;;) {
    // Read the epoch before polling: a frame sent after the poll changes it, so no wake-up is lost.
    const std::uint64_t epoch = clock_.OutputEpoch();
    const hw::CanStatus status = endpoint_.Receive(frame, 0, info);
    if (status == hw::CanStatus::kOk) return status;
    const std::int64_t now_ns = clock_.NowNs();
    if (status == hw::CanStatus::kBusOff && (!bus_off_on_entry || now_ns >= deadline_ns)) {
      return status;
    }
    if (status != hw::CanStatus::kTimeout && status != hw::CanStatus::kBusOff) return status;
    if (now_ns >= deadline_ns) {
      timeouts_.fetch_add(1, std::memory_order_relaxed);
      return hw::CanStatus::kTimeout;
    }
    std::int64_t wake_at_ns = deadline_ns;
    const std::int64_t bus_idle_ns = bus_.BusIdleAtNs();  // a frame in flight ends by then
    if (bus_idle_ns > now_ns) wake_at_ns = std::min(wake_at_ns, bus_idle_ns);
    try {
      clock_.WaitForOutput(wake_at_ns, epoch);
    } catch (...) {
      return hw::CanStatus::kError;  // the clock's mutex failed: nothing sensible to wait on
    }
  }
}

hw::CanBusStatistics ClockedCanEndpoint::Statistics() const noexcept {
  hw::CanBusStatistics statistics = endpoint_.Statistics();
  statistics.timeouts = timeouts_.load(std::memory_order_relaxed);
  return statistics;
}

}  // namespace hrgbench::drivers::sim_station
