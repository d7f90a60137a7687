// The non-real-time parts of capture.hpp: run validation, the result's report, and the consumer's
// Drain.

#include <cstdio>
#include <span>

#include "hrgbench/bench/capture/capture.hpp"

namespace hrgbench::bench {

bool CaptureRun::IsValid(std::string* why) const {
  auto fail = [why](const std::string& message) {
    if (why != nullptr) *why = message;
    return false;
  };
  if (sample_count == 0 && deadline_ns == 0) {
    return fail("no stop condition: set sample_count or deadline_ns (a run must be bounded)");
  }
  if (read_timeout_ns <= 0) {
    return fail("read_timeout_ns = " + std::to_string(read_timeout_ns) + " must be > 0");
  }
  if (max_silence_ns < 0) {
    return fail("max_silence_ns = " + std::to_string(max_silence_ns) + " must be >= 0");
  }
  if (realtime.priority < 0) {
    return fail("realtime.priority = " + std::to_string(realtime.priority) +
                " must be >= 0 (0 = off)");
  }
  if (realtime.cpu < -1) {
    return fail("realtime.cpu = " + std::to_string(realtime.cpu) + " must be >= -1 (-1 = any)");
  }
  return true;
}

std::string_view ToString(CaptureTermination termination) noexcept {
  switch (termination) {
    case CaptureTermination::kNotStarted:
      return "not started";
    case CaptureTermination::kCountReached:
      return "count reached";
    case CaptureTermination::kDeadline:
      return "deadline";
    case CaptureTermination::kStopRequested:
      return "stop requested";
    case CaptureTermination::kDeviceNotRunning:
      return "device not running";
    case CaptureTermination::kBusOff:
      return "bus-off";
    case CaptureTermination::kDeviceError:
      return "device error";
    case CaptureTermination::kStalled:
      return "stalled";
  }
  return "?";
}

hw::GyroCounters CaptureResult::CounterDelta() const noexcept {
  return hw::CountersSince(counters_at_start, counters_at_end);
}

std::string CaptureResult::Report() const {
  if (termination == CaptureTermination::kNotStarted) return "Capture was not started.";
  const hw::GyroCounters d = CounterDelta();
  char text[1024];
  std::snprintf(
      text, sizeof(text),
      "Capture ended: %s after %.3f s. %llu samples read, %llu pushed (seq %u..%u), %llu lost to "
      "a full ring, %llu past the run's end, %llu out of order. %llu sequence gaps with %llu "
      "samples missing. %llu reads, %llu timed out; largest batch %zu, ring high water %zu. "
      "Device during the run: %llu frames, %llu bad, %llu kernel drops, %llu driver buffer "
      "overruns, %llu bus errors.",
      std::string(ToString(termination)).c_str(), static_cast<double>(ended_ns - started_ns) * 1e-9,
      static_cast<unsigned long long>(samples_read),
      static_cast<unsigned long long>(samples_pushed), any_sample ? first_seq : 0u,
      any_sample ? last_seq : 0u, static_cast<unsigned long long>(ring_overruns),
      static_cast<unsigned long long>(samples_after_end),
      static_cast<unsigned long long>(sequence_regressions),
      static_cast<unsigned long long>(sequence_gaps),
      static_cast<unsigned long long>(samples_missing), static_cast<unsigned long long>(reads),
      static_cast<unsigned long long>(read_timeouts), max_batch, ring_high_water,
      static_cast<unsigned long long>(d.frames_received),
      static_cast<unsigned long long>(d.bad_frames),
      static_cast<unsigned long long>(d.kernel_drops),
      static_cast<unsigned long long>(d.buffer_overruns),
      static_cast<unsigned long long>(d.bus_errors));
  return std::string(text) + " Real-time: " + realtime.Summary() + ".";
}

std::size_t Drain(SampleRing& ring, std::vector<hw::GyroSample>& out) {
  // Size() from the consumer is a lower bound of what Pop finds (only the producer adds), so the
  // resize below is never too large; Pop's count trims it anyway.
  const std::size_t queued = ring.Size();
  if (queued == 0) return 0;
  const std::size_t old_size = out.size();
  out.resize(old_size + queued);
  const std::size_t popped = ring.Pop(std::span<hw::GyroSample>(out).subspan(old_size));
  out.resize(old_size + popped);
  return popped;
}

}  // namespace hrgbench::bench
