#pragma once
// One node of a VirtualCanBus (see virtual_can_bus.hpp for the bus model). Implements CanBus with
// the contract of hrgbench/hw/can_bus.hpp, plus fault injection on this node. Created only by
// VirtualCanBus::CreateEndpoint; must be destroyed before its bus.
//
// Implementation notes on the CanBus contract:
//   - Send never waits: the bus timeline absorbs any backlog (kBufferFull is never returned).
//   - Receive: frames wait in a preallocated FrameRing; a full ring drops its oldest frame and
//     counts it (Statistics().dropped_frames and the next ReceiveInfo::dropped_frames).
//   - Timestamps: the end-of-frame time on the bus's Clock, reported as kHardware (exact, like a
//     controller's stamp). State() starts kErrorActive. Concurrent Receive calls are safe here.

#include <array>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <span>
#include <vector>

#include "can_virtual/frame_ring.hpp"
#include "hrgbench/hw/can_bus.hpp"

namespace hrgbench::drivers::can_virtual {

class VirtualCanBus;

struct VirtualCanEndpointOptions {
  // Receive this endpoint's own frames too (SocketCAN: CAN_RAW_RECV_OWN_MSGS). Off as on CAN.
  bool receive_own_frames = false;
  // Receive queue size; 0 = the bus's queue_capacity.
  std::size_t queue_capacity = 0;
  // Transmit queue (a controller's mailboxes and its driver's queue), frames; 0 = unlimited. On a
  // timed bus a frame waits in it until its end of frame has passed; when it holds this many, Send
  // returns kBufferFull and the frame is not sent: a node whose bus is overloaded loses frames
  // at its source, as on a real bus, instead of falling ever further behind.
  std::size_t transmit_queue_frames = 0;
};

class VirtualCanEndpoint final : public hw::CanBus {
 public:
  ~VirtualCanEndpoint() override;
  VirtualCanEndpoint(const VirtualCanEndpoint&) = delete;
  VirtualCanEndpoint& operator=(const VirtualCanEndpoint&) = delete;

  hw::CanStatus Send(const hw::CanFrame& frame, std::int64_t timeout_ns) noexcept override;
  hw::CanStatus Receive(hw::CanFrame* frame, std::int64_t timeout_ns,
                        hw::ReceiveInfo* info) noexcept override;
  hw::CanStatus SetFilters(std::span<const hw::CanFilter> filters) noexcept override;
  hw::CanBusStatistics Statistics() const noexcept override;
  hw::CanBusState State() const noexcept override;
  bool SupportsFd() const noexcept override;

  // Forces the controller state, as an error frame would. kBusOff: Send returns kBusOff, frames
  // on the bus are not received, a waiting Receive returns kBusOff once its queue is empty.
  // Any other state puts the node back on the bus. Counts one error frame. Any thread.
  void InjectState(hw::CanBusState state) noexcept;

 private:
  friend class VirtualCanBus;
  VirtualCanEndpoint(VirtualCanBus* bus, const VirtualCanEndpointOptions& options,
                     std::size_t queue_capacity);

  // Called by the bus with the bus mutex held. Applies state and filters, then queues.
  void Deliver(const hw::CanFrame& frame, std::int64_t deliver_at_ns) noexcept;
  bool AcceptsUnderMutex(const hw::CanFrame& frame) const noexcept;
  // Waits until `wake_at_ns` on the bus clock or a notification; `lock` holds mutex_.
  void WaitUntil(std::unique_lock<std::mutex>& lock, std::int64_t wake_at_ns) noexcept;

  VirtualCanBus* const bus_;
  const VirtualCanEndpointOptions options_;

  mutable std::mutex mutex_;  // guards everything below
  std::condition_variable frame_or_state_changed_;
  FrameRing queue_;
  std::array<hw::CanFilter, hw::kMaxCanFilters> filters_{};
  std::size_t filter_count_ = 0;
  bool filters_set_ = false;  // until SetFilters: accept everything
  std::uint32_t drops_since_last_frame_ = 0;
  hw::CanBusState state_ = hw::CanBusState::kErrorActive;
  hw::CanBusStatistics statistics_;
  // End-of-frame times of the frames in the transmit queue, oldest first (a ring of
  // transmit_queue_frames, allocated at construction; in bus order, so increasing).
  std::vector<std::int64_t> transmit_ends_ns_;
  std::size_t transmit_head_ = 0;
  std::size_t transmit_count_ = 0;
};

}  // namespace hrgbench::drivers::can_virtual
