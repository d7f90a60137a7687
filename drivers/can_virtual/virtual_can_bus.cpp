#include "can_virtual/virtual_can_bus.hpp"

#include <algorithm>

#include "hrgbench/hw/can_frame_bits.hpp"

namespace hrgbench::drivers::can_virtual {

bool VirtualCanBusOptions::IsValid(std::string* why) const {
  const auto fail = [why](const char* reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (nominal_bit_rate_bps < 0) return fail("nominal_bit_rate_bps must be >= 0 (0 = untimed)");
  if (data_bit_rate_bps < 0) return fail("data_bit_rate_bps must be >= 0 (0 = nominal)");
  if (queue_capacity == 0) return fail("queue_capacity must be >= 1");
  if (!(drop_probability >= 0.0 && drop_probability <= 1.0)) {
    return fail("drop_probability must be in [0, 1]");
  }
  if (!(corrupt_probability >= 0.0 && corrupt_probability <= 1.0)) {
    return fail("corrupt_probability must be in [0, 1]");
  }
  return true;
}

std::expected<std::unique_ptr<VirtualCanBus>, std::string> VirtualCanBus::Create(
    const VirtualCanBusOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) return std::unexpected("VirtualCanBus options: " + why);
  return std::unique_ptr<VirtualCanBus>(new VirtualCanBus(options));
}

VirtualCanBus::VirtualCanBus(const VirtualCanBusOptions& options)
    : options_(options),
      clock_(options.clock != nullptr ? options.clock : &steady_clock_),
      rng_(options.seed) {
  // Endpoints are usually few; reserving keeps CreateEndpoint from reallocating in common cases.
  endpoints_.reserve(8);
}

VirtualCanBus::~VirtualCanBus() = default;

std::unique_ptr<VirtualCanEndpoint> VirtualCanBus::CreateEndpoint(
    const VirtualCanEndpointOptions& options) {
  const std::size_t capacity =
      options.queue_capacity > 0 ? options.queue_capacity : options_.queue_capacity;
  std::unique_ptr<VirtualCanEndpoint> endpoint(new VirtualCanEndpoint(this, options, capacity));
  const std::lock_guard lock(mutex_);
  endpoints_.push_back(endpoint.get());
  return endpoint;
}

void VirtualCanBus::Detach(const VirtualCanEndpoint* endpoint) noexcept {
  const std::lock_guard lock(mutex_);
  std::erase(endpoints_, endpoint);
}

void VirtualCanBus::DropNext(std::uint32_t count) noexcept {
  const std::lock_guard lock(mutex_);
  drop_next_ += count;
}

void VirtualCanBus::CorruptNext(std::uint32_t count) noexcept {
  const std::lock_guard lock(mutex_);
  corrupt_next_ += count;
}

void VirtualCanBus::SetBusOff(bool bus_off) noexcept {
  const std::lock_guard lock(mutex_);
  for (VirtualCanEndpoint* endpoint : endpoints_) {
    endpoint->InjectState(bus_off ? hw::CanBusState::kBusOff : hw::CanBusState::kErrorActive);
  }
}

VirtualCanBusStatistics VirtualCanBus::Statistics() const noexcept {
  const std::lock_guard lock(mutex_);
  return statistics_;
}

std::int64_t VirtualCanBus::BusIdleAtNs() const noexcept {
  const std::lock_guard lock(mutex_);
  return bus_idle_at_ns_;
}

bool VirtualCanBus::DrawUnderMutex(double probability) noexcept {
  if (probability <= 0.0) return false;
  // 53 random mantissa bits: uniform in [0, 1) without a distribution object's state.
  const double u = static_cast<double>(rng_() >> 11) * 0x1.0p-53;
  return u < probability;
}

std::int64_t VirtualCanBus::Transmit(const VirtualCanEndpoint* sender,
                                     const hw::CanFrame& frame) noexcept {
  const std::lock_guard lock(mutex_);
  const std::int64_t now_ns = clock_->NowNs();
  std::int64_t end_of_frame_ns = now_ns;
  if (options_.nominal_bit_rate_bps > 0) {
    // The frame starts when the bus is idle and occupies it for its bit time; a lost or corrupted
    // frame still used the bus.
    const std::int64_t start_ns = std::max(now_ns, bus_idle_at_ns_);
    end_of_frame_ns =
        start_ns + hw::FrameDurationNs(options_.stuff_bits ? hw::StuffedFrameBits(frame)
                                                           : hw::CountFrameBits(frame),
                                       options_.nominal_bit_rate_bps, options_.data_bit_rate_bps);
    bus_idle_at_ns_ = end_of_frame_ns;
    statistics_.busy_ns += end_of_frame_ns - start_ns;
  }
  ++statistics_.frames_on_bus;

  bool drop = false;
  if (drop_next_ > 0) {
    --drop_next_;
    drop = true;
  } else {
    drop = DrawUnderMutex(options_.drop_probability);
  }
  if (drop) {
    ++statistics_.injected_drops;
    return end_of_frame_ns;
  }

  hw::CanFrame on_wire = frame;
  const bool carries_data = !frame.remote && frame.length > 0;
  if (carries_data) {
    bool corrupt = false;
    if (corrupt_next_ > 0) {
      --corrupt_next_;
      corrupt = true;
    } else {
      corrupt = DrawUnderMutex(options_.corrupt_probability);
    }
    if (corrupt) {
      // A bit flip the CRC did not catch: the worst case for a protocol, which must notice it
      // itself (range checks, its own checksum).
      const std::uint64_t bit = rng_() % (8u * frame.length);
      on_wire.data[bit / 8] = static_cast<std::uint8_t>(on_wire.data[bit / 8] ^ (1u << (bit % 8)));
      ++statistics_.injected_corruptions;
    }
  }

  for (VirtualCanEndpoint* endpoint : endpoints_) {
    if (endpoint == sender && !endpoint->options_.receive_own_frames) continue;
    endpoint->Deliver(on_wire, end_of_frame_ns);
  }
  return end_of_frame_ns;
}

}  // namespace hrgbench::drivers::can_virtual
