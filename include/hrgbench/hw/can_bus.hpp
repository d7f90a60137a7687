#pragma once
// CanBus: a CAN / CAN FD transport, as the protocol drivers (gyro_can) see it. Implementations:
// SocketCanBus (drivers/socketcan, Linux CAN_RAW) and the endpoints of VirtualCanBus
// (drivers/can_virtual, in-process). A protocol driver holds a CanBus&, never a concrete class.
//
// Contract common to every method:
//   - Expected conditions (timeout, bus-off, full transmit queue, bad frame) are CanStatus values;
//     no method throws (all are noexcept).
//   - Times are nanoseconds (`*_ns`). Timeouts are relative budgets, measured on the transport's
//     own time base (the steady clock, or the Clock a virtual bus was given). A relative budget
//     keeps callers independent of which clock a transport uses.
//   - Threads: one thread may Send while another Receives. Statistics(), State() and SupportsFd()
//     may be called from any thread at any time. SetFilters() may be called from any thread; it
//     applies to frames that arrive after it returns. Concurrent Receive() calls on the same
//     object are NOT part of the contract (SocketCanBus reuses one receive buffer).
//   - Real-time safety: Send() and Receive() do not allocate and take no unbounded lock; they
//     block only up to their timeout. SetFilters() may take a lock but does not allocate for up
//     to kMaxCanFilters filters.
// No vendor header here: the Linux CAN ABI stays inside drivers/socketcan.

#include <cstdint>
#include <span>
#include <string_view>

#include "hrgbench/hw/can_frame.hpp"

namespace hrgbench::hw {

enum class CanStatus : std::uint8_t {
  kOk,               // done
  kTimeout,          // Receive: no frame within the timeout (not an error; counted in timeouts)
  kBusOff,           // the controller is bus-off: nothing sent / no frame returned
  kBufferFull,       // Send: the transmit queue stayed full until the timeout (ENOBUFS)
  kNotOpen,          // the transport is closed or was never opened
  kInvalidFrame,     // Send: the frame is malformed or not supported (FD on a classic bus)
  kInvalidArgument,  // SetFilters: too many filters; null pointer arguments
  kError,            // any other failure of the underlying transport (counted, see Statistics)
};

constexpr std::string_view ToString(CanStatus status) noexcept {
  switch (status) {
    case CanStatus::kOk:
      return "ok";
    case CanStatus::kTimeout:
      return "timeout";
    case CanStatus::kBusOff:
      return "bus-off";
    case CanStatus::kBufferFull:
      return "buffer full";
    case CanStatus::kNotOpen:
      return "not open";
    case CanStatus::kInvalidFrame:
      return "invalid frame";
    case CanStatus::kInvalidArgument:
      return "invalid argument";
    case CanStatus::kError:
      return "error";
  }
  return "?";
}

// The fault-confinement state of the local CAN controller (ISO 11898-1), as last reported.
enum class CanBusState : std::uint8_t {
  kUnknown,       // nothing reported yet (SocketCAN reports only changes)
  kErrorActive,   // normal operation, error counters < 96
  kErrorWarning,  // an error counter reached 96
  kErrorPassive,  // an error counter reached 128
  kBusOff,        // transmit error counter passed 255: the node is off the bus
};

constexpr std::string_view ToString(CanBusState state) noexcept {
  switch (state) {
    case CanBusState::kUnknown:
      return "unknown";
    case CanBusState::kErrorActive:
      return "error-active";
    case CanBusState::kErrorWarning:
      return "error-warning";
    case CanBusState::kErrorPassive:
      return "error-passive";
    case CanBusState::kBusOff:
      return "bus-off";
  }
  return "?";
}

// Where a receive timestamp came from. kHardware: stamped by the CAN controller (jitter-free end
// of frame); kSoftware: stamped by the kernel when the frame was queued to the socket; kNone: no
// stamp available (timestamp_ns is then the transport's clock at the return of Receive).
enum class TimestampSource : std::uint8_t { kNone, kSoftware, kHardware };

constexpr std::string_view ToString(TimestampSource source) noexcept {
  switch (source) {
    case TimestampSource::kNone:
      return "none";
    case TimestampSource::kSoftware:
      return "software";
    case TimestampSource::kHardware:
      return "hardware";
  }
  return "?";
}

struct ReceiveInfo {
  // Time the frame was received, in ns. Time base: the transport's, stated by each implementation
  // (SocketCAN: CLOCK_REALTIME for software stamps, the controller's clock for hardware stamps;
  // VirtualCanBus: its Clock). Compare stamps of one source with each other, not across sources.
  std::int64_t timestamp_ns = 0;
  TimestampSource timestamp_source = TimestampSource::kNone;
  // Frames this receiver lost (kernel socket queue overflow, SO_RXQ_OVFL, or a full virtual
  // queue) since the previous frame returned by Receive. Non-zero means a gap before this frame.
  std::uint32_t dropped_frames = 0;
};

// Acceptance filter, SocketCAN semantics: a frame passes when (frame.id & mask) == (id & mask)
// and frame.extended == extended. Remote and data frames both pass. Several filters are OR-ed.
struct CanFilter {
  std::uint32_t id = 0;
  std::uint32_t mask = 0;
  bool extended = false;
};
inline constexpr std::size_t kMaxCanFilters = 32;

// Cumulative counters since open, one per failure kind (STYLE rule 5). Never reset.
struct CanBusStatistics {
  std::uint64_t frames_sent = 0;          // Send() returned kOk
  std::uint64_t frames_received = 0;      // Receive() returned kOk (data and remote frames)
  std::uint64_t error_frames = 0;         // error frames from the controller (consumed for State())
  std::uint64_t send_errors = 0;          // Send() returned kError or kBusOff
  std::uint64_t receive_errors = 0;       // Receive() returned kError
  std::uint64_t invalid_frames = 0;       // Send() refused a frame (kInvalidFrame), or a malformed
                                          // frame was received and discarded
  std::uint64_t dropped_frames = 0;       // receive-side losses (kernel overflow / virtual queue)
  std::uint64_t buffer_full_retries = 0;  // Send() retries after ENOBUFS / EAGAIN
  std::uint64_t buffer_full = 0;          // Send() returned kBufferFull
  std::uint64_t timeouts = 0;             // Receive() returned kTimeout
};

// True when `frame` may be sent: identifier within its 11/29 bits, a length valid for its kind
// (classic ≤ 8; FD one of 0..8, 12, 16, 20, 24, 32, 48, 64), no remote FD frame, BRS only on FD,
// not an error frame, and FD only when `fd_enabled`. Pure, real-time safe.
constexpr bool IsValidCanFrame(const CanFrame& frame, bool fd_enabled) noexcept {
  if (frame.error) return false;
  const std::uint32_t id_mask =
      frame.extended ? CanFrame::kExtendedIdMask : CanFrame::kStandardIdMask;
  if ((frame.id & ~id_mask) != 0) return false;
  if (!frame.fd) return !frame.bit_rate_switch && frame.length <= CanFrame::kMaxClassicLength;
  if (!fd_enabled || frame.remote) return false;
  const std::uint8_t n = frame.length;
  return n <= 8 || n == 12 || n == 16 || n == 20 || n == 24 || n == 32 || n == 48 || n == 64;
}

class CanBus {
 public:
  virtual ~CanBus() = default;

  // Queues `frame` for transmission. Waits at most `timeout_ns` for room in the transmit queue
  // (0: try once). Returns kOk once the transport accepted the frame (not: once it was
  // acknowledged on the bus), kBufferFull if the queue stayed full until the timeout, kBusOff if
  // the controller is bus-off, kInvalidFrame if !IsValidCanFrame(frame, SupportsFd()) (nothing
  // sent), kNotOpen, or kError. Real-time safe; noexcept.
  virtual CanStatus Send(const CanFrame& frame, std::int64_t timeout_ns) noexcept = 0;

  // Waits at most `timeout_ns` (0: poll once) for the next frame that passes the filters and
  // writes it to `*frame` (data bytes beyond `length` are zero) and its stamp to `*info` (`info`
  // may be null). Frames from one sender arrive in the order sent. Returns kOk, kTimeout (a normal
  // outcome), kBusOff when no frame is returned because the controller is or went bus-off,
  // kInvalidArgument if `frame` is null, kNotOpen, or kError. Error frames are consumed to update
  // State() and counted, not returned. Real-time safe (no allocation); noexcept.
  virtual CanStatus Receive(CanFrame* frame, std::int64_t timeout_ns,
                            ReceiveInfo* info) noexcept = 0;

  // Replaces the acceptance filters (see CanFilter). Until the first call every frame passes; an
  // empty span lets no frame pass. At most kMaxCanFilters: more returns kInvalidArgument and keeps
  // the previous filters. Frames already queued for this receiver are not re-filtered.
  virtual CanStatus SetFilters(std::span<const CanFilter> filters) noexcept = 0;

  // A consistent-enough snapshot of the counters (each counter is exact; the set is not taken
  // atomically). Any thread; real-time safe.
  virtual CanBusStatistics Statistics() const noexcept = 0;

  // The controller state from the last error report (kUnknown until one arrived). Any thread.
  virtual CanBusState State() const noexcept = 0;

  // True when CAN FD frames can be sent and received (SocketCAN: the interface MTU is CANFD_MTU).
  virtual bool SupportsFd() const noexcept = 0;
};

}  // namespace hrgbench::hw
