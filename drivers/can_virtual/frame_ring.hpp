#pragma once
// A bounded FIFO of frames for one virtual endpoint, allocated once at construction. When full,
// Push overwrites the OLDEST frame and reports it: a receiver that fell behind gets the freshest
// data (what a streaming consumer wants), and the gap is counted and reported with the next frame
// (ReceiveInfo::dropped_frames). SocketCAN drops the newest instead; either way a sequence counter
// in the protocol sees the gap. Not thread-safe: the endpoint's mutex guards it.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "hrgbench/hw/can_frame.hpp"

namespace hrgbench::drivers::can_virtual {

struct QueuedFrame {
  hw::CanFrame frame;
  std::int64_t deliver_at_ns = 0;  // end of frame on the bus: not visible to Receive before
};

class FrameRing {
 public:
  explicit FrameRing(std::size_t capacity) : slots_(capacity > 0 ? capacity : 1) {}

  // Appends; returns true if the oldest frame was overwritten to make room. No allocation.
  bool Push(const QueuedFrame& entry) noexcept {
    bool overwrote = false;
    if (size_ == slots_.size()) {
      head_ = Next(head_);
      --size_;
      overwrote = true;
    }
    slots_[(head_ + size_) % slots_.size()] = entry;
    ++size_;
    return overwrote;
  }
  bool Empty() const noexcept { return size_ == 0; }
  std::size_t Size() const noexcept { return size_; }
  std::size_t Capacity() const noexcept { return slots_.size(); }
  // Precondition: !Empty().
  const QueuedFrame& Front() const noexcept { return slots_[head_]; }
  void PopFront() noexcept {
    head_ = Next(head_);
    --size_;
  }

 private:
  std::size_t Next(std::size_t i) const noexcept { return i + 1 == slots_.size() ? 0 : i + 1; }

  std::vector<QueuedFrame> slots_;
  std::size_t head_ = 0;
  std::size_t size_ = 0;
};

}  // namespace hrgbench::drivers::can_virtual
