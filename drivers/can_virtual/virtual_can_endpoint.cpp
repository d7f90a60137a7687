#include "can_virtual/virtual_can_endpoint.hpp"

#include <algorithm>
#include <chrono>

#include "can_virtual/virtual_can_bus.hpp"

namespace hrgbench::drivers::can_virtual {

using hw::CanBusState;
using hw::CanStatus;

VirtualCanEndpoint::VirtualCanEndpoint(VirtualCanBus* bus, const VirtualCanEndpointOptions& options,
                                       std::size_t queue_capacity)
    : bus_(bus),
      options_(options),
      queue_(queue_capacity),
      transmit_ends_ns_(options.transmit_queue_frames) {}

VirtualCanEndpoint::~VirtualCanEndpoint() { bus_->Detach(this); }

bool VirtualCanEndpoint::SupportsFd() const noexcept { return bus_->options_.fd; }

CanStatus VirtualCanEndpoint::Send(const hw::CanFrame& frame,
                                   std::int64_t /*timeout_ns*/) noexcept {
  {
    const std::lock_guard lock(mutex_);
    if (!hw::IsValidCanFrame(frame, SupportsFd())) {
      ++statistics_.invalid_frames;
      return CanStatus::kInvalidFrame;
    }
    if (state_ == CanBusState::kBusOff) {
      ++statistics_.send_errors;
      return CanStatus::kBusOff;
    }
    if (!transmit_ends_ns_.empty()) {
      const std::int64_t now_ns = bus_->clock().NowNs();
      while (transmit_count_ > 0 && transmit_ends_ns_[transmit_head_] <= now_ns) {
        transmit_head_ = (transmit_head_ + 1) % transmit_ends_ns_.size();
        --transmit_count_;
      }
      if (transmit_count_ == transmit_ends_ns_.size()) {
        ++statistics_.buffer_full;
        return CanStatus::kBufferFull;
      }
    }
  }
  // The endpoint lock is released first: the bus takes its own lock, then receivers' locks (and
  // ours, with receive_own_frames).
  const std::int64_t end_of_frame_ns = bus_->Transmit(this, frame);
  const std::lock_guard lock(mutex_);
  ++statistics_.frames_sent;
  if (!transmit_ends_ns_.empty()) {
    transmit_ends_ns_[(transmit_head_ + transmit_count_) % transmit_ends_ns_.size()] =
        end_of_frame_ns;
    ++transmit_count_;
  }
  return CanStatus::kOk;
}

void VirtualCanEndpoint::Deliver(const hw::CanFrame& frame, std::int64_t deliver_at_ns) noexcept {
  {
    const std::lock_guard lock(mutex_);
    if (state_ == CanBusState::kBusOff || !AcceptsUnderMutex(frame)) return;
    QueuedFrame entry{frame, deliver_at_ns};
    // Bytes beyond the length are zero on receive, as the CanBus contract promises.
    std::fill(entry.frame.data.begin() + (frame.remote ? 0 : frame.length), entry.frame.data.end(),
              std::uint8_t{0});
    if (queue_.Push(entry)) {
      ++statistics_.dropped_frames;
      ++drops_since_last_frame_;
    }
  }
  frame_or_state_changed_.notify_all();
}

bool VirtualCanEndpoint::AcceptsUnderMutex(const hw::CanFrame& frame) const noexcept {
  if (!filters_set_) return true;
  for (std::size_t i = 0; i < filter_count_; ++i) {
    const hw::CanFilter& f = filters_[i];
    if (f.extended == frame.extended && ((frame.id ^ f.id) & f.mask) == 0) return true;
  }
  return false;
}

void VirtualCanEndpoint::WaitUntil(std::unique_lock<std::mutex>& lock,
                                   std::int64_t wake_at_ns) noexcept {
  const hw::Clock& clock = *bus_->clock_;
  const std::int64_t wait_ns = wake_at_ns - clock.NowNs();
  if (wait_ns <= 0) return;
  if (bus_->options_.clock == nullptr) {
    // Steady clock: real time, and a new frame or state change wakes us at once.
    frame_or_state_changed_.wait_for(lock, std::chrono::nanoseconds(wait_ns));
    return;
  }
  // A caller-supplied clock runs on its own time: wait in that time, without our lock so senders
  // can deliver meanwhile.
  lock.unlock();
  bus_->clock_->SleepForNs(wait_ns);
  lock.lock();
}

CanStatus VirtualCanEndpoint::Receive(hw::CanFrame* frame, std::int64_t timeout_ns,
                                      hw::ReceiveInfo* info) noexcept {
  if (frame == nullptr) return CanStatus::kInvalidArgument;
  const hw::Clock& clock = *bus_->clock_;
  const std::int64_t deadline_ns = clock.NowNs() + std::max<std::int64_t>(timeout_ns, 0);
  std::unique_lock lock(mutex_);
  // Bus-off on entry: wait out the timeout (a caller's loop must not spin) and then say why
  // nothing came; going bus-off during the wait: return at once.
  const bool bus_off_on_entry = state_ == CanBusState::kBusOff;
  for (;;) {
    const std::int64_t now_ns = clock.NowNs();
    std::int64_t wake_at_ns = deadline_ns;
    if (!queue_.Empty()) {
      const QueuedFrame& head = queue_.Front();
      if (head.deliver_at_ns <= now_ns) {
        *frame = head.frame;
        if (info != nullptr) {
          info->timestamp_ns = head.deliver_at_ns;
          info->timestamp_source = hw::TimestampSource::kHardware;
          info->dropped_frames = drops_since_last_frame_;
        }
        drops_since_last_frame_ = 0;
        queue_.PopFront();
        ++statistics_.frames_received;
        return CanStatus::kOk;
      }
      wake_at_ns = std::min(wake_at_ns, head.deliver_at_ns);
    } else if (state_ == CanBusState::kBusOff && !bus_off_on_entry) {
      return CanStatus::kBusOff;
    }
    if (now_ns >= deadline_ns) {
      if (state_ == CanBusState::kBusOff) return CanStatus::kBusOff;
      ++statistics_.timeouts;
      return CanStatus::kTimeout;
    }
    WaitUntil(lock, wake_at_ns);
  }
}

CanStatus VirtualCanEndpoint::SetFilters(std::span<const hw::CanFilter> filters) noexcept {
  if (filters.size() > hw::kMaxCanFilters) return CanStatus::kInvalidArgument;
  const std::lock_guard lock(mutex_);
  std::copy(filters.begin(), filters.end(), filters_.begin());
  filter_count_ = filters.size();
  filters_set_ = true;
  return CanStatus::kOk;
}

hw::CanBusStatistics VirtualCanEndpoint::Statistics() const noexcept {
  const std::lock_guard lock(mutex_);
  return statistics_;
}

CanBusState VirtualCanEndpoint::State() const noexcept {
  const std::lock_guard lock(mutex_);
  return state_;
}

void VirtualCanEndpoint::InjectState(CanBusState state) noexcept {
  {
    const std::lock_guard lock(mutex_);
    state_ = state;
    ++statistics_.error_frames;
  }
  frame_or_state_changed_.notify_all();
}

}  // namespace hrgbench::drivers::can_virtual
