#pragma once
// VirtualCanBus: an in-process CAN bus for tests and simulation, no kernel needed. A hub with any
// number of endpoints; each endpoint is a CanBus. A frame sent on one endpoint is delivered, in
// bus order, to every OTHER endpoint whose filters accept it (a sender sees its own frames only
// with receive_own_frames, like CAN_RAW_RECV_OWN_MSGS). Every receiver sees the frames of all
// senders in the same order: the hub serialises transmissions as a real bus does (in order of
// Send calls; arbitration by identifier priority between simultaneous senders is not modelled).
//
// Timing: with nominal_bit_rate_bps > 0 a frame occupies the bus for its bit time (see
// hrgbench/hw/can_frame_bits.hpp; 111 µs for an 8-byte classic frame at 1 Mbit/s, plus its stuff
// bits with stuff_bits), frames queue
// behind each other on the bus, and a receiver sees a frame only once its end of frame has passed
// on the bus's Clock; the frame's timestamp is that end-of-frame time. With 0 (default) delivery is
// immediate and stamped with the clock at Send.
//
// Faults (explicit failure modes, STYLE rule 6): DropNext(n) / drop_probability lose a frame for
// every receiver (the sender's Send still returns kOk: nobody counts such a loss, only a protocol
// sequence counter sees it); CorruptNext(n) / corrupt_probability flip one data bit of frames
// that carry data; SetBusOff / VirtualCanEndpoint::InjectState take nodes off the bus.
// Probabilistic faults use a seeded std::mt19937_64, so a run is reproducible from its seed.
//
// Threads: every method of the hub and of its endpoints may be called from any thread. Lock
// order: hub mutex, then an endpoint's mutex. The hub must outlive its endpoints.

#include <cstddef>
#include <cstdint>
#include <expected>
#include <memory>
#include <mutex>
#include <random>
#include <string>
#include <vector>

#include "can_virtual/virtual_can_endpoint.hpp"
#include "hrgbench/hw/can_bus.hpp"
#include "hrgbench/hw/clock.hpp"

namespace hrgbench::drivers::can_virtual {

struct VirtualCanBusOptions {
  // Arbitration-phase bit rate; 0 = untimed (instant delivery). 1'000'000 models a 1 Mbit/s bus.
  std::int64_t nominal_bit_rate_bps = 0;
  // Time each classic frame with the stuff bits its own bit stream needs (hw::StuffedFrameBits;
  // FD frames at their worst case), as a real bus does; false: no stuff bits (the best case).
  bool stuff_bits = false;
  // CAN FD data-phase bit rate for frames with BRS; 0 = same as nominal.
  std::int64_t data_bit_rate_bps = 0;
  // Whether endpoints accept CAN FD frames (SupportsFd()). A classic bus refuses FD frames.
  bool fd = true;
  // Frames each endpoint can hold unread before the oldest is dropped. 1024 is ~0.1 s of a fully
  // loaded 1 Mbit/s bus, more than a socket's default receive buffer holds.
  std::size_t queue_capacity = 1024;
  // Probabilities per frame on the bus, in [0, 1]; drawn from an RNG seeded with `seed`.
  double drop_probability = 0.0;
  double corrupt_probability = 0.0;
  std::uint64_t seed = 1;
  // Time base for timing, timestamps and timeouts; not owned, must outlive the bus. nullptr: the
  // steady clock, and Receive waits on a condition variable (woken at once by a new frame). With
  // any other clock (ManualClock) Receive waits with Clock::SleepForNs in that clock's time, so a
  // single-threaded test with an auto-advancing ManualClock sees timeouts and bit times as jumps.
  hw::Clock* clock = nullptr;

  // False, with the reason, for negative rates, zero capacity or probabilities outside [0, 1].
  bool IsValid(std::string* why) const;
};

struct VirtualCanBusStatistics {
  std::uint64_t frames_on_bus = 0;         // frames transmitted by any endpoint
  std::uint64_t injected_drops = 0;        // frames lost by drop injection
  std::uint64_t injected_corruptions = 0;  // frames with a flipped data bit
  std::int64_t busy_ns = 0;  // time frames occupied the bus (timed bus only): busy_ns / elapsed
                             // is its load
};

class VirtualCanBus {
 public:
  static std::expected<std::unique_ptr<VirtualCanBus>, std::string> Create(
      const VirtualCanBusOptions& options);
  ~VirtualCanBus();
  VirtualCanBus(const VirtualCanBus&) = delete;
  VirtualCanBus& operator=(const VirtualCanBus&) = delete;

  // A new node on the bus (allocates its queue: setup, not real-time). Any thread.
  std::unique_ptr<VirtualCanEndpoint> CreateEndpoint(const VirtualCanEndpointOptions& options = {});

  // Lose the next `count` frames on the bus (added to any pending count).
  void DropNext(std::uint32_t count) noexcept;
  // Flip one data bit in each of the next `count` frames that carry data.
  void CorruptNext(std::uint32_t count) noexcept;
  // Every endpoint goes bus-off (true) or back to error-active (false): a shorted bus.
  void SetBusOff(bool bus_off) noexcept;

  VirtualCanBusStatistics Statistics() const noexcept;
  // When the bus becomes idle, on the bus's clock (≤ now when idle or untimed).
  std::int64_t BusIdleAtNs() const noexcept;
  const VirtualCanBusOptions& options() const noexcept { return options_; }
  const hw::Clock& clock() const noexcept { return *clock_; }

 private:
  friend class VirtualCanEndpoint;
  explicit VirtualCanBus(const VirtualCanBusOptions& options);

  // Called by an endpoint's Send (without the endpoint's lock held). Returns the frame's end of
  // frame on the bus's clock.
  std::int64_t Transmit(const VirtualCanEndpoint* sender, const hw::CanFrame& frame) noexcept;
  void Detach(const VirtualCanEndpoint* endpoint) noexcept;
  bool DrawUnderMutex(double probability) noexcept;

  VirtualCanBusOptions options_;
  hw::SteadyClock steady_clock_;
  hw::Clock* clock_;

  mutable std::mutex mutex_;  // guards everything below
  std::vector<VirtualCanEndpoint*> endpoints_;
  std::int64_t bus_idle_at_ns_ = 0;
  std::uint32_t drop_next_ = 0;
  std::uint32_t corrupt_next_ = 0;
  std::mt19937_64 rng_;
  VirtualCanBusStatistics statistics_;
};

}  // namespace hrgbench::drivers::can_virtual
