#pragma once
// SpscRing<T>: a bounded, lock-free single-producer single-consumer ring. The capture thread (the
// producer) pushes decoded gyro samples; the non-real-time side (sequencer / recorder, the
// consumer) pops them. Header-only.
//
// Capacity: fixed at construction, a power of two (index → slot is a mask, no division). The
// storage is allocated and value-initialised once in the constructor (the zero fill faults its
// pages in, so the first pushes of a run do not page-fault); nothing allocates afterwards.
//
// Full ring: the push is refused (the newest items are dropped, the ones already queued are kept
// in order) and the producer counts each refused item in Overruns(). A consumer sees the loss as
// a gap in whatever sequence number T carries; the ring never overwrites unread items.
//
// Threads: exactly ONE producer thread calls the Push functions and exactly ONE consumer thread
// the Pop functions (which threads may change between runs, given a happens-before edge such as
// std::thread start/join). Size(), Empty(), Overruns(), Pushed(), Popped() and capacity() may be
// called from any thread; Size() is then a snapshot that may be stale by the time it is used.
//
// Real-time safety: every function except the constructor is noexcept, lock-free (two atomics
// that are always lock-free on x86-64/AArch64), wait-free (no retry loop) and allocation-free.
//
// Memory ordering (why it is data-race free, and why ThreadSanitizer agrees): the producer
// writes slots, then publishes them with a release store of write_index_; the consumer acquires
// write_index_ before reading those slots. The consumer releases read_index_ after it has read
// its slots; the producer acquires read_index_ before it reuses them. Every slot access is thus
// ordered by a release/acquire pair on the index that hands the slot over; no slot is ever
// accessed by both threads without one. The indices count items since construction (64 bits: at
// 10^9 items/s they wrap after 584 years), so full (write − read == capacity) and empty (write ==
// read) are distinct without a wasted slot.
//
// Layout: each side's index, its cached copy of the other side's index and its counters share
// one cache line, and the two sides' lines are separate (alignas(kCacheLineBytes)), so the
// producer and the consumer only share a line when one of them actually has to read the other's
// index (when its cached copy says full / empty). 64 bytes: the x86-64 and most AArch64 line;
// std::hardware_destructive_interference_size is not used because g++ 12 warns (-Winterference-
// size) that its value is not ABI-stable across -mtune, and warnings are errors here.
//
// Failure modes: a capacity that is not a power of two in [2, 2^32] throws std::invalid_argument
// from the constructor (a programming error, caught at setup, never in a loop); allocation
// failure throws std::bad_alloc from the constructor. Nothing fails afterwards.

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace hrgbench::bench {

inline constexpr std::size_t kCacheLineBytes = 64;

template <typename T>
class SpscRing {
  // Items are copied with plain assignment / std::copy (memmove for trivially copyable types):
  // no constructor that could throw or allocate runs in the real-time path.
  static_assert(std::is_trivially_copyable_v<T>, "SpscRing holds trivially copyable items");
  static_assert(std::is_nothrow_default_constructible_v<T>);
  static_assert(std::atomic<std::uint64_t>::is_always_lock_free);

 public:
  static constexpr std::size_t kMaxCapacity = std::size_t{1} << 32;

  static constexpr bool IsValidCapacity(std::size_t capacity) noexcept {
    return capacity >= 2 && capacity <= kMaxCapacity && std::has_single_bit(capacity);
  }

  // Allocates `capacity` slots (value-initialised). Throws std::invalid_argument unless
  // IsValidCapacity(capacity); std::bad_alloc when out of memory. Not real-time safe.
  explicit SpscRing(std::size_t capacity)
      : capacity_(CheckedCapacity(capacity)),
        mask_(capacity_ - 1),
        slots_(std::make_unique<T[]>(capacity_)) {}

  SpscRing(const SpscRing&) = delete;
  SpscRing& operator=(const SpscRing&) = delete;

  // ---- Producer thread only ----

  // Appends `item`. Returns false, and counts one overrun, when the ring is full.
  bool TryPush(const T& item) noexcept {
    const std::uint64_t write = producer_.write_index.load(std::memory_order_relaxed);
    if (write - producer_.cached_read_index == capacity_) {
      producer_.cached_read_index = consumer_.read_index.load(std::memory_order_acquire);
      if (write - producer_.cached_read_index == capacity_) {
        CountOverruns(1);
        return false;
      }
    }
    slots_[write & mask_] = item;
    producer_.write_index.store(write + 1, std::memory_order_release);
    return true;
  }

  // Appends as many of `items` as fit, in order, and returns how many. The rest (the newest) are
  // refused and counted as overruns. One release store publishes the whole batch.
  std::size_t Push(std::span<const T> items) noexcept {
    if (items.empty()) return 0;
    const std::uint64_t write = producer_.write_index.load(std::memory_order_relaxed);
    std::size_t free = capacity_ - static_cast<std::size_t>(write - producer_.cached_read_index);
    if (free < items.size()) {
      producer_.cached_read_index = consumer_.read_index.load(std::memory_order_acquire);
      free = capacity_ - static_cast<std::size_t>(write - producer_.cached_read_index);
    }
    const std::size_t n = std::min(free, items.size());
    CopyIn(write, items.first(n));
    if (n > 0) producer_.write_index.store(write + n, std::memory_order_release);
    if (n < items.size()) CountOverruns(items.size() - n);
    return n;
  }

  // ---- Consumer thread only ----

  // Removes the oldest item into `out`. Returns false when the ring is empty.
  bool TryPop(T& out) noexcept {
    const std::uint64_t read = consumer_.read_index.load(std::memory_order_relaxed);
    if (read == consumer_.cached_write_index) {
      consumer_.cached_write_index = producer_.write_index.load(std::memory_order_acquire);
      if (read == consumer_.cached_write_index) return false;
    }
    out = slots_[read & mask_];
    consumer_.read_index.store(read + 1, std::memory_order_release);
    return true;
  }

  // Removes up to out.size() of the oldest items into `out`, in order; returns how many.
  std::size_t Pop(std::span<T> out) noexcept {
    if (out.empty()) return 0;
    const std::uint64_t read = consumer_.read_index.load(std::memory_order_relaxed);
    std::size_t available = static_cast<std::size_t>(consumer_.cached_write_index - read);
    if (available < out.size()) {
      consumer_.cached_write_index = producer_.write_index.load(std::memory_order_acquire);
      available = static_cast<std::size_t>(consumer_.cached_write_index - read);
    }
    const std::size_t n = std::min(available, out.size());
    CopyOut(read, out.first(n));
    if (n > 0) consumer_.read_index.store(read + n, std::memory_order_release);
    return n;
  }

  // ---- Any thread ----

  std::size_t capacity() const noexcept { return capacity_; }
  // Items queued now (a snapshot; exact only when both sides are quiescent).
  std::size_t Size() const noexcept {
    // Read first, then write: write ≥ read then holds even while both sides run, since write
    // only grows and was ≥ read when read was loaded.
    const std::uint64_t read = consumer_.read_index.load(std::memory_order_acquire);
    const std::uint64_t write = producer_.write_index.load(std::memory_order_acquire);
    return static_cast<std::size_t>(write - read);
  }
  bool Empty() const noexcept { return Size() == 0; }
  // Items accepted / handed out since construction, and items refused because the ring was full.
  std::uint64_t Pushed() const noexcept {
    return producer_.write_index.load(std::memory_order_acquire);
  }
  std::uint64_t Popped() const noexcept {
    return consumer_.read_index.load(std::memory_order_acquire);
  }
  std::uint64_t Overruns() const noexcept {
    return producer_.overruns.load(std::memory_order_relaxed);
  }

 private:
  static std::size_t CheckedCapacity(std::size_t capacity) {
    if (!IsValidCapacity(capacity)) {
      throw std::invalid_argument("SpscRing capacity " + std::to_string(capacity) +
                                  " is not a power of two in [2, 2^32]");
    }
    return capacity;
  }

  // Copies into slots starting at index `first`, in at most two contiguous pieces (wrap-around).
  void CopyIn(std::uint64_t first, std::span<const T> items) noexcept {
    const std::size_t start = static_cast<std::size_t>(first & mask_);
    const std::size_t head = std::min(items.size(), capacity_ - start);
    std::copy(items.begin(), items.begin() + static_cast<std::ptrdiff_t>(head), &slots_[start]);
    std::copy(items.begin() + static_cast<std::ptrdiff_t>(head), items.end(), &slots_[0]);
  }
  void CopyOut(std::uint64_t first, std::span<T> out) const noexcept {
    const std::size_t start = static_cast<std::size_t>(first & mask_);
    const std::size_t head = std::min(out.size(), capacity_ - start);
    std::copy(&slots_[start], &slots_[start] + head, out.begin());
    std::copy(&slots_[0], &slots_[0] + (out.size() - head),
              out.begin() + static_cast<std::ptrdiff_t>(head));
  }
  // Single writer (the producer): a load + store, no read-modify-write needed.
  void CountOverruns(std::size_t n) noexcept {
    producer_.overruns.store(producer_.overruns.load(std::memory_order_relaxed) + n,
                             std::memory_order_relaxed);
  }

  // Read-only after construction: shared freely by both sides.
  const std::size_t capacity_;
  const std::size_t mask_;
  const std::unique_ptr<T[]> slots_;

  // Written by the producer; read by the consumer only when its cached copy says "empty".
  struct alignas(kCacheLineBytes) ProducerSide {
    std::atomic<std::uint64_t> write_index{0};
    std::uint64_t cached_read_index = 0;  // producer-private copy of read_index
    std::atomic<std::uint64_t> overruns{0};
  };
  // Written by the consumer; read by the producer only when its cached copy says "full".
  struct alignas(kCacheLineBytes) ConsumerSide {
    std::atomic<std::uint64_t> read_index{0};
    std::uint64_t cached_write_index = 0;  // consumer-private copy of write_index
  };
  ProducerSide producer_;
  ConsumerSide consumer_;
};

}  // namespace hrgbench::bench
