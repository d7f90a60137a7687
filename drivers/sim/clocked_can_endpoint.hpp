#pragma once
// ClockedCanEndpoint: a VirtualCanEndpoint whose blocking Receive waits on a VirtualTimeClock,
// woken at once by any frame sent on the bus. hw::CanBus contract as hw/can_bus.hpp, with the
// endpoint's notes (virtual_can_endpoint.hpp); this wrapper changes only how Receive waits.
//
// Why: a VirtualCanEndpoint given a caller's clock waits with Clock::SleepForNs, which nothing
// interrupts: a frame that arrives during the wait is seen at the end of the timeout. On a
// VirtualTimeClock the wrapper waits with WaitForOutput instead: the clock wakes it when a
// participant (the simulated gyro) sent something or when a Send through any ClockedCanEndpoint
// of the station called NotifyOutput. On a timed bus (bit rate > 0) a frame becomes visible at its
// end of frame, so the wait is also bounded by VirtualCanBus::BusIdleAtNs().
//
// Receive polls the endpoint with a zero timeout; those polls are not counted as timeouts:
// Statistics().timeouts counts this wrapper's own timed-out Receive calls.
//
// Threads: as VirtualCanEndpoint (one Send and one Receive thread at once). Real-time safety:
// Send and Receive do not allocate; they take the clock's mutex (not a real-time path anyway in
// simulated time). The endpoint, bus and clock must outlive this.

#include <atomic>
#include <cstdint>
#include <span>

#include "can_virtual/virtual_can_bus.hpp"
#include "can_virtual/virtual_can_endpoint.hpp"
#include "hrgbench/hw/can_bus.hpp"
#include "sim/virtual_time_clock.hpp"

namespace hrgbench::drivers::sim_station {

class ClockedCanEndpoint final : public hw::CanBus {
 public:
  ClockedCanEndpoint(can_virtual::VirtualCanBus& bus, can_virtual::VirtualCanEndpoint& endpoint,
                     VirtualTimeClock& clock)
      : bus_(bus), endpoint_(endpoint), clock_(clock) {}

  hw::CanStatus Send(const hw::CanFrame& frame, std::int64_t timeout_ns) noexcept override;
  hw::CanStatus Receive(hw::CanFrame* frame, std::int64_t timeout_ns,
                        hw::ReceiveInfo* info) noexcept override;
  hw::CanStatus SetFilters(std::span<const hw::CanFilter> filters) noexcept override {
    return endpoint_.SetFilters(filters);
  }
  hw::CanBusStatistics Statistics() const noexcept override;
  hw::CanBusState State() const noexcept override { return endpoint_.State(); }
  bool SupportsFd() const noexcept override { return endpoint_.SupportsFd(); }

 private:
  can_virtual::VirtualCanBus& bus_;
  can_virtual::VirtualCanEndpoint& endpoint_;
  VirtualTimeClock& clock_;
  std::atomic<std::uint64_t> timeouts_{0};
};

}  // namespace hrgbench::drivers::sim_station
