#pragma once
// GyroElectronics: the HRG's control electronics as the bench sees them. The electronics excite the
// resonator's standing wave to a commanded state (a, b, θ), hold it there, release it to free run
// on command (t = 0 of a run), stream the four demodulated pick-off channels y1..y4 at the
// configured rate, and report their status. Concrete electronics: GyroCanDevice
// (drivers/gyro_can, the CAN protocol hrg_gyro_v2.dbc) over any CanBus; the simulated electronics
// (drivers/sim) speak the same protocol.
//
// Sequence of a run:  Configure → Excite → WaitReady → Release → ReadSamples … → Stop.
//
// Units: rates in Hz, angles in rad, times in ns (`*_ns`) on the time base of the transport's
// receive stamps (see hw/can_bus.hpp: ReceiveInfo::timestamp_ns), y in the electronics' amplitude
// unit (the model's unit: a = 1 is the nominal excitation amplitude).
//
// Threads: an implementation is owned by ONE thread (the capture thread). State(), Counters() and
// LastStatus() may be read from any thread. No other method is thread-safe.
// Real-time safety: ReadSamples(), State(), Counters() and LastStatus() are real-time safe (no
// allocation, no unbounded wait) and noexcept. The setup methods are not: they may allocate an
// error message and block for their documented time bound.
// Failure modes are values: setup methods return std::expected<_, GyroError>; nothing throws
// except std::bad_alloc from an error message.

#include <cstdint>
#include <expected>
#include <limits>
#include <span>
#include <string>
#include <string_view>

namespace hrgbench::hw {

// Mode of the electronics as reported in their status, mirrored by the host driver's state
// machine (GyroElectronics::State()). The numbers are the wire values (hrg_gyro_v2.dbc, Mode).
enum class GyroMode : std::uint8_t {
  kIdle = 0,        // powered, no sample rate configured, wave not driven
  kConfigured = 1,  // sample rate set; wave not driven
  kExciting = 2,    // amplitude and angle control loops are driving the wave to its target
  kReady = 3,       // the wave is held at the commanded (a, b, θ): release is possible
  kFreeRun = 4,     // control off, the wave decays freely; samples are streaming
  kStopped = 5,     // safe state: drive off, wave damped, no samples
  kFaulted = 6,     // a fault (see fault bits) or a lost bus: only Stop() leaves it
  // the gyro as a gyro (whole-angle): the energy and quadrature loops closed with the unit's
  // compensation parameters, the wave free to turn, the angle output streaming
  kOperating = 7,
};

constexpr std::string_view ToString(GyroMode mode) noexcept {
  switch (mode) {
    case GyroMode::kIdle:
      return "idle";
    case GyroMode::kConfigured:
      return "configured";
    case GyroMode::kExciting:
      return "exciting";
    case GyroMode::kReady:
      return "ready";
    case GyroMode::kFreeRun:
      return "free-run";
    case GyroMode::kStopped:
      return "stopped";
    case GyroMode::kFaulted:
      return "faulted";
    case GyroMode::kOperating:
      return "operating";
  }
  return "?";
}

// Fault bits of GyroStatus::fault_bits (wire values, hrg_gyro_v2.dbc Fault* signals).
namespace gyro_fault {
inline constexpr std::uint8_t kPllUnlock = 1u << 0;        // drive PLL lost the resonance
inline constexpr std::uint8_t kOverTemperature = 1u << 1;  // resonator housing above its limit
inline constexpr std::uint8_t kExciteTimeout = 1u << 2;    // wave did not reach its target
inline constexpr std::uint8_t kDriveSaturation = 1u << 3;  // drive amplifier at its rail
inline constexpr std::uint8_t kSampleOverrun = 1u << 4;    // samples lost at the source (TX full)
inline constexpr std::uint8_t kBusError = 1u << 5;         // the node saw CAN errors / recovered
inline constexpr std::uint8_t kConfigRejected = 1u << 6;   // last configure was out of range
inline constexpr std::uint8_t kInternal = 1u << 7;         // watchdog reset, memory error
}  // namespace gyro_fault

struct GyroStatus {
  std::int64_t t_ns = 0;               // receive stamp of the status frame (0: none received yet)
  GyroMode mode = GyroMode::kIdle;     // the electronics' own mode
  std::uint8_t fault_bits = 0;         // gyro_fault bits, 0 = healthy
  bool pll_lock = false;               // drive PLL locked on the resonance
  bool ready = false;                  // wave at the commanded state (mode kReady)
  double resonant_frequency_hz = 0.0;  // the PLL's frequency, Hz (resolution 1 mHz)
  double temperature_c = 0.0;          // resonator housing, °C (resolution 0.01 °C)
};

// The standing wave's state to excite (orbit elements at release, see estimator/model.hpp Orbit;
// the phase φ is the electronics' own and not commanded).
struct WaveState {
  double a = 1.0;          // amplitude, (0, 6.5535], resolution 1e-4
  double b = 0.0;          // quadrature, |b| ≤ 3.2767 and |b| < a, resolution 1e-4
  double theta_rad = 0.0;  // wave angle, |θ| ≤ 3.2767 rad, resolution 1e-4 rad
};

struct GyroConfig {
  std::uint32_t sample_rate_hz = 1000;  // 1 … the transport's limit (below)
  // What Release does: let the wave decay freely (a free run, the measurement), or close the
  // whole-angle loops and stream the gyro's angle output (the operating mode).
  bool whole_angle = false;
};

// What the gyro link can carry, whatever electronics sit behind it (the CAN protocol v2;
// drivers/gyro_can/gyro_protocol.hpp static_asserts that it agrees): a plan is judged against
// these before any hardware is touched (`hrg-bench check`), not refused at run time.
inline constexpr std::uint32_t kMaxSampleRateClassicCanHz = 2000;  // two 8-byte frames a sample
inline constexpr std::uint32_t kMaxSampleRateCanFdHz = 10000;      // five samples a 64-byte frame
inline constexpr std::uint32_t MaxSampleRateHz(bool can_fd) noexcept {
  return can_fd ? kMaxSampleRateCanFdHz : kMaxSampleRateClassicCanHz;
}
// The status frame reports the resonant frequency as an unsigned 24-bit count of mHz.
inline constexpr double kMaxReportedResonantFrequencyHz = 16777.215;

// One sample of the four demodulated channels.
struct GyroSample {
  std::uint32_t seq = 0;  // sample number since the release (0 = the release instant); a gap in
                          // seq is a lost sample, already counted in GyroCounters
  std::int64_t t_ns = 0;  // release stamp + seq / sample_rate, on the electronics' sample clock
                          // mapped to the receive time base (no bus jitter)
  double y[4] = {0.0, 0.0, 0.0, 0.0};  // y1..y4, amplitude units, quantised to the wire's LSB
  // The demodulation reference's phase χ the electronics reported for this sample (relative to
  // the reference locked at release), rad; y has been turned back by it (y1 + i·y2 and y3 + i·y4
  // times e^{+iχ}), so y is as if the reference had stayed locked. NaN: not reported (electronics
  // without it, or before their first report), y as received.
  double reference_phase_rad = std::numeric_limits<double>::quiet_NaN();
  // The conditions of the electronics' last status report decoded before this sample (GyroStatus,
  // same units and resolution), so the record has them over the run, not only at its ends;
  // deterministic in the order of the frames, so a replay of the CAN log gives the same. NaN: no
  // status received yet.
  double temperature_c = std::numeric_limits<double>::quiet_NaN();
  double resonant_frequency_hz = std::numeric_limits<double>::quiet_NaN();
};

// One counter per failure kind (STYLE rule 5), cumulative since construction, never reset.
struct GyroCounters {
  std::uint64_t frames_received = 0;    // every frame Receive returned
  std::uint64_t samples_decoded = 0;    // complete samples delivered to the sample buffer
  std::uint64_t bad_frames = 0;         // wrong length, checksum, or field value: discarded
  std::uint64_t sequence_gaps = 0;      // breaks in the sample sequence (events)
  std::uint64_t samples_lost = 0;       // samples missing in those gaps
  std::uint64_t timeouts = 0;           // command attempts without an ack + sample reads that
                                        // timed out
  std::uint64_t kernel_drops = 0;       // frames the transport dropped (socket queue overflow)
  std::uint64_t buffer_overruns = 0;    // samples discarded because the host buffer was full
  std::uint64_t command_retries = 0;    // command attempts after the first
  std::uint64_t nacks = 0;              // commands the electronics refused
  std::uint64_t bus_errors = 0;         // bus-off or transport errors seen
  std::uint64_t unexpected_frames = 0;  // valid frames not expected now (stale acks, stray ids)
  std::uint64_t reference_phases_missing = 0;  // samples delivered without the reference phase
                                               // their electronics report (its report lost)
};

// What happened between two readings of the same device's counters (cumulative, never reset, so
// later − earlier is the interval's count of each kind).
constexpr GyroCounters CountersSince(const GyroCounters& earlier, const GyroCounters& later) {
  GyroCounters d;
  d.frames_received = later.frames_received - earlier.frames_received;
  d.samples_decoded = later.samples_decoded - earlier.samples_decoded;
  d.bad_frames = later.bad_frames - earlier.bad_frames;
  d.sequence_gaps = later.sequence_gaps - earlier.sequence_gaps;
  d.samples_lost = later.samples_lost - earlier.samples_lost;
  d.timeouts = later.timeouts - earlier.timeouts;
  d.kernel_drops = later.kernel_drops - earlier.kernel_drops;
  d.buffer_overruns = later.buffer_overruns - earlier.buffer_overruns;
  d.command_retries = later.command_retries - earlier.command_retries;
  d.nacks = later.nacks - earlier.nacks;
  d.bus_errors = later.bus_errors - earlier.bus_errors;
  d.unexpected_frames = later.unexpected_frames - earlier.unexpected_frames;
  d.reference_phases_missing = later.reference_phases_missing - earlier.reference_phases_missing;
  return d;
}

enum class GyroErrorCode : std::uint8_t {
  kInvalidArgument,   // a value out of its documented range: nothing sent
  kInvalidState,      // not allowed in the current State(): nothing sent
  kTimeout,           // no acknowledgement after every attempt / not ready in time
  kRejected,          // the electronics answered with a negative acknowledgement
  kBusOff,            // the transport is bus-off: State() is kFaulted
  kTransport,         // any other transport failure
  kFaulted,           // the electronics report a fault (see the message and LastStatus())
  kReadBackMismatch,  // the acknowledged value differs from the commanded one
};

constexpr std::string_view ToString(GyroErrorCode code) noexcept {
  switch (code) {
    case GyroErrorCode::kInvalidArgument:
      return "invalid argument";
    case GyroErrorCode::kInvalidState:
      return "invalid state";
    case GyroErrorCode::kTimeout:
      return "timeout";
    case GyroErrorCode::kRejected:
      return "rejected";
    case GyroErrorCode::kBusOff:
      return "bus-off";
    case GyroErrorCode::kTransport:
      return "transport";
    case GyroErrorCode::kFaulted:
      return "faulted";
    case GyroErrorCode::kReadBackMismatch:
      return "read-back mismatch";
  }
  return "?";
}

struct GyroError {
  GyroErrorCode code = GyroErrorCode::kTransport;
  std::string message;  // what went wrong, with the values involved

  std::string ToString() const { return std::string(hw::ToString(code)) + ": " + message; }
};

// Outcome of one ReadSamples call (no allocation, so no message).
enum class GyroReadStatus : std::uint8_t {
  kOk,          // `count` ≥ 1 samples written
  kTimeout,     // no sample within the timeout (counted in GyroCounters::timeouts)
  kNotRunning,  // State() is not kFreeRun and no buffered sample is left
  kBusOff,      // the transport went bus-off: State() is now kFaulted
  kError,       // another transport failure (counted in bus_errors)
};

struct GyroReadResult {
  std::size_t count = 0;
  GyroReadStatus status = GyroReadStatus::kOk;
};

class GyroElectronics {
 public:
  virtual ~GyroElectronics() = default;

  // Sets the sample rate and reads it back from the acknowledgement. Allowed in kIdle,
  // kConfigured and kStopped; → kConfigured. Bounded: attempts × ack timeout (implementation's
  // config). Failure: kInvalidArgument (rate out of range, nothing sent), kInvalidState,
  // kTimeout, kRejected, kReadBackMismatch, kBusOff, kTransport.
  virtual std::expected<void, GyroError> Configure(const GyroConfig& config) = 0;

  // Commands the control loops to drive the wave to `target`. Allowed in kConfigured and kReady
  // (re-excite); → kExciting. Returns once acknowledged, not when the wave is there (WaitReady).
  // Failure: as Configure.
  virtual std::expected<void, GyroError> Excite(const WaveState& target) = 0;

  // Waits, polling the status, until the electronics report the wave at its target (→ kReady) or
  // `timeout_ns` passes (kTimeout). Allowed in kExciting and kReady. Failure: kTimeout,
  // kFaulted (a fault bit or mode kFaulted reported: → kFaulted), kBusOff, kTransport.
  virtual std::expected<GyroStatus, GyroError> WaitReady(std::int64_t timeout_ns) = 0;

  // Releases the wave to free run. Acknowledged and timestamped: returns the release instant in
  // ns on the receive time base — t = 0 of the run, the time of sample seq 0. Allowed in kReady;
  // → kFreeRun. Samples may already be streaming when it returns. Failure: as Configure.
  virtual std::expected<std::int64_t, GyroError> Release() = 0;

  // Stops to the safe state (drive off, wave damped, stream stopped). Allowed in every state,
  // including kFaulted (the way out of it); → kStopped. Failure: as Configure; on kBusOff or
  // kTimeout the state is kFaulted (the electronics' own watchdog is then the safety net).
  virtual std::expected<void, GyroError> Stop() = 0;

  // Requests a status frame and waits for it (bounded as Configure). Any state except kFaulted
  // by bus-off. Updates LastStatus(). Failure: kTimeout, kBusOff, kTransport.
  virtual std::expected<GyroStatus, GyroError> RequestStatus() = 0;

  // Copies up to out.size() samples into `out`: returns as soon as at least one is available
  // (after draining what has already arrived, up to out.size()), or after `timeout_ns` (0: poll).
  // Samples are in seq order; gaps are counted, never filled. Real-time safe: no allocation, no
  // lock beyond the transport's; noexcept. Frames that are not samples (status, stale acks) are
  // consumed and accounted for. Failure: see GyroReadStatus.
  virtual GyroReadResult ReadSamples(std::span<GyroSample> out,
                                     std::int64_t timeout_ns) noexcept = 0;

  // The host's state machine (mirrors the electronics' mode). Any thread; real-time safe.
  virtual GyroMode State() const noexcept = 0;
  // The last status frame received (t_ns = 0 if none yet). Any thread; real-time safe.
  virtual GyroStatus LastStatus() const noexcept = 0;
  // Any thread; real-time safe; each counter exact, the set not taken atomically.
  virtual GyroCounters Counters() const noexcept = 0;
};

}  // namespace hrgbench::hw
