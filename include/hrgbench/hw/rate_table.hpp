#pragma once
// RateTable: a single-axis rate table commanded in rate mode. The bench's sequencer sees only this
// interface; concrete tables (Modbus TCP/RTU driver, in-process simulation) live in drivers/ and
// are picked by the one factory in src/app.
//
// Units: rates in rad/s (positive = counter-clockwise seen from above the table top, the sign the
// gyro reports as +Omega), accelerations in rad/s^2, times in s or ns as the name says.
//
// Threads: an implementation is owned by ONE thread (the sequencer's). No method is thread-safe
// unless it says so; a transport context (e.g. libmodbus' modbus_t) is never shared between
// threads. Real-time safety: no method is real-time safe (they do I/O and may allocate an error
// message); do not call them from the capture loop.
//
// Failure modes are values: every method that can fail returns std::expected<_, RateTableError>;
// nothing throws except std::bad_alloc. SafeStop() and Disconnect() cannot fail and never throw.

#include <cmath>
#include <cstdint>
#include <expected>
#include <numbers>
#include <string>

namespace hrgbench::hw {

enum class RateTableMode : std::uint16_t {
  kIdle = 0,  // drive enabled, holding zero rate (decelerates at the acceleration limit)
  kRate = 1,  // follows the commanded rate, slewing at the acceleration limit
};

// Fault codes a table reports (the register map in drivers/modbus_rate_table/README.md carries the
// same numbers). A table may report codes outside this list; they are kept as raw numbers.
enum class RateTableFault : std::uint16_t {
  kNone = 0,
  kWatchdog = 1,   // heartbeats stopped for longer than the table's watchdog timeout
  kEStop = 2,      // emergency stop pressed
  kInterlock = 3,  // the enclosure interlock opened while moving, or a move was commanded open
  kOverspeed = 4,  // measured rate beyond the table's own hardware limit
  kDrive = 5,      // amplifier / motor fault
};

// "watchdog", "e-stop", ... or "fault <n>" for an unknown code.
inline std::string RateTableFaultName(std::uint16_t fault_code) {
  switch (static_cast<RateTableFault>(fault_code)) {
    case RateTableFault::kNone:
      return "none";
    case RateTableFault::kWatchdog:
      return "watchdog";
    case RateTableFault::kEStop:
      return "e-stop";
    case RateTableFault::kInterlock:
      return "interlock";
    case RateTableFault::kOverspeed:
      return "overspeed";
    case RateTableFault::kDrive:
      return "drive";
  }
  return "fault " + std::to_string(fault_code);
}

// One status read: everything arrives in one transaction, so the fields are consistent.
struct RateTableStatus {
  std::int64_t t_ns = 0;              // when the reply arrived, on the driver's Clock
  double commanded_rate_rad_s = 0.0;  // the setpoint the table is slewing towards
  double measured_rate_rad_s = 0.0;   // the table's encoder-derived rate
  RateTableMode mode = RateTableMode::kIdle;
  bool rate_stable = false;          // the table's own "at rate" bit (its tolerance, its dwell)
  bool in_motion = false;            // the table top is turning or ramping
  bool fault = false;                // a latched fault; see fault_code; cleared by a fault reset
  bool estop = false;                // emergency stop active (also sets fault)
  bool interlock_open = false;       // enclosure interlock open: the table refuses to move
  std::uint16_t fault_code = 0;      // RateTableFault value, 0 when no fault
  double temperature_c = 0.0;        // table electronics temperature (°C), as reported
  std::uint16_t heartbeat_echo = 0;  // last heartbeat value the table received
};

// One read of the table top's encoder angle. A table knows its mean rate over a run far better
// from its angle than from its rate readings: (angle_end - angle_start) / (t_end - t_start) is the
// exact mean of the true rate, whatever the rate did in between, and its error does not grow with
// the run (bench/run_omega.hpp turns a run's readings into Ω and its standard error).
//
// The count is the encoder's, modulo 2^32: it wraps, so use differences of successive readings
// (exact while the table turns less than 2^31 counts between them: 256 revolutions at 2^23
// counts/rev). counts_per_rev need not divide 2^32, so a single count is not an angle modulo 2π.
//
// Time: t_ns is on the caller's bench clock (the implementation's injected Clock), the midpoint of
// the read (request sent .. reply received); the table sampled its encoder somewhere in
// t_ns ± window_ns / 2 (0 for an in-process table that samples at the clock's now). The angle's
// time error is therefore at most window_ns / 2, and |Ω| · window_ns / sqrt(12) rad of angle when
// it is taken as uniform in the window.
struct RateTableAngle {
  std::int64_t t_ns = 0;             // bench clock, midpoint of the read
  std::int64_t window_ns = 0;        // reply time - request time, >= 0
  std::uint32_t count = 0;           // encoder count, modulo 2^32
  std::uint32_t counts_per_rev = 0;  // encoder resolution as the table reports it (> 0 if valid)
  bool valid = false;                // the table vouches for the position (no encoder error)

  double RadPerCount() const noexcept {
    return counts_per_rev == 0 ? 0.0 : 2.0 * std::numbers::pi / counts_per_rev;
  }
};

enum class RateTableErrorCode {
  kInvalidConfig,     // a config value is out of range (message names it)
  kNotConnected,      // called before Connect() or after the link was given up
  kConnectFailed,     // could not open the link within the bounded attempts
  kConnectionLost,    // the link dropped and the bounded reconnects failed
  kTimeout,           // no (complete) reply within the response timeout, after bounded retries
  kExceptionReply,    // the table answered with a Modbus exception (message has the code)
  kBadReply,          // a reply of the wrong length, CRC or content
  kLimitExceeded,     // a software limit rejected the value; nothing was sent
  kReadBackMismatch,  // what the table reports back differs from what was written
  kFaulted,           // the table reports a fault (or e-stop); reset it before moving
  kNotStable,         // WaitUntilStable: the stable conditions did not hold within the timeout
  kProtocol,          // the peer is not a table of the documented map (e.g. map version)
  kNotSupported,      // the table does not offer this (e.g. no angle registers in its map)
};

struct RateTableError {
  RateTableErrorCode code = RateTableErrorCode::kNotConnected;
  std::string message;  // what went wrong, with the values involved

  // "<code name>: <message>"
  std::string ToString() const;
};

inline const char* RateTableErrorCodeName(RateTableErrorCode code) {
  switch (code) {
    case RateTableErrorCode::kInvalidConfig:
      return "invalid config";
    case RateTableErrorCode::kNotConnected:
      return "not connected";
    case RateTableErrorCode::kConnectFailed:
      return "connect failed";
    case RateTableErrorCode::kConnectionLost:
      return "connection lost";
    case RateTableErrorCode::kTimeout:
      return "timeout";
    case RateTableErrorCode::kExceptionReply:
      return "exception reply";
    case RateTableErrorCode::kBadReply:
      return "bad reply";
    case RateTableErrorCode::kLimitExceeded:
      return "limit exceeded";
    case RateTableErrorCode::kReadBackMismatch:
      return "read-back mismatch";
    case RateTableErrorCode::kFaulted:
      return "faulted";
    case RateTableErrorCode::kNotStable:
      return "not stable";
    case RateTableErrorCode::kProtocol:
      return "protocol";
    case RateTableErrorCode::kNotSupported:
      return "not supported";
  }
  return "unknown";
}

inline std::string RateTableError::ToString() const {
  return std::string(RateTableErrorCodeName(code)) + ": " + message;
}

// What "at a stable rate" means for WaitUntilStable: the table's rate-stable bit AND
// |measured - commanded by us| <= tolerance_rad_s AND no fault bit, continuously for dwell_s.
struct StableCriteria {
  double tolerance_rad_s = 1e-3;  // accepted |measured - target|; above the table's rate noise
  double dwell_s = 1.0;           // the conditions must hold this long without a break
  double timeout_s = 60.0;        // give up (kNotStable) after this long; covers the ramp time
  double poll_period_s = 0.05;    // time between status reads while waiting

  // False (and *why says which field and value) when a field is not finite and positive, or
  // dwell_s > timeout_s.
  bool IsValid(std::string* why) const {
    const auto check = [why](const char* name, double value) {
      if (std::isfinite(value) && value > 0.0) return true;
      if (why != nullptr)
        *why = std::string(name) + " must be finite and > 0, got " + std::to_string(value);
      return false;
    };
    if (!check("tolerance_rad_s", tolerance_rad_s) || !check("dwell_s", dwell_s) ||
        !check("timeout_s", timeout_s) || !check("poll_period_s", poll_period_s)) {
      return false;
    }
    if (dwell_s > timeout_s) {
      if (why != nullptr)
        *why = "dwell_s (" + std::to_string(dwell_s) + ") exceeds timeout_s (" +
               std::to_string(timeout_s) + ")";
      return false;
    }
    return true;
  }
};

class RateTable {
 public:
  virtual ~RateTable() = default;

  // Opens the link, checks the peer is a table of the expected kind, writes and reads back the
  // configuration (acceleration limit, watchdog timeout). Bounded in time by the implementation's
  // config (attempts x connect timeout). Calling it while connected reconnects.
  // Failure: kInvalidConfig, kConnectFailed, kProtocol, kReadBackMismatch, kTimeout.
  virtual std::expected<void, RateTableError> Connect() = 0;

  // Commands rate mode at `rate_rad_s`. Software limits (|rate| and finite) are checked before
  // anything is sent. The table slews at its acceleration limit; this returns once the command is
  // written and read back, not when the rate is reached (see WaitUntilStable).
  // Failure: kLimitExceeded (nothing sent), kNotConnected, kFaulted, kTimeout, kExceptionReply,
  // kBadReply, kConnectionLost, kReadBackMismatch.
  virtual std::expected<void, RateTableError> SetRate(double rate_rad_s) = 0;

  // Sets the table's acceleration limit (rad/s^2, > 0), checked against the software limit first.
  // Same failure modes as SetRate.
  virtual std::expected<void, RateTableError> SetAccelerationLimit(double accel_rad_s2) = 0;

  // One status read (one transaction). Failure: kNotConnected, kTimeout, kExceptionReply,
  // kBadReply, kConnectionLost. A table fault is NOT an error here: it is in the status.
  virtual std::expected<RateTableStatus, RateTableError> ReadStatus() = 0;

  // Polls ReadStatus() every criteria.poll_period_s until the stable conditions (StableCriteria)
  // hold for dwell_s; returns the last status. Keeps the heartbeat alive while waiting.
  // Failure: kFaulted (fault bit seen), kNotStable (timeout_s passed), transport errors as
  // ReadStatus, kInvalidConfig (criteria).
  virtual std::expected<RateTableStatus, RateTableError> WaitUntilStable(
      const StableCriteria& criteria) = 0;

  // One read of the encoder angle (one transaction), stamped on the implementation's clock (see
  // RateTableAngle). A table without an angle readout answers kNotSupported, every time, without
  // any I/O; the caller then measures Ω from the rate readings. A table fault is not an error
  // here (the angle of a stopped table is still its angle). Failure: kNotSupported, kNotConnected,
  // kTimeout, kExceptionReply, kBadReply (e.g. a reported resolution of 0), kConnectionLost.
  virtual std::expected<RateTableAngle, RateTableError> ReadAngle() = 0;

  // Refreshes the table's watchdog. Every other call refreshes it too when it is due; the owner
  // must call some method at least every heartbeat period while the table may move (documented by
  // the implementation), else the table stops itself. Failure: transport errors.
  virtual std::expected<void, RateTableError> Heartbeat() = 0;

  // Clears a latched fault (the table keeps it if the cause persists, e.g. e-stop still pressed).
  virtual std::expected<void, RateTableError> ResetFault() = 0;

  // Commands zero rate (idle mode) and reports whether the table accepted it.
  virtual std::expected<void, RateTableError> Stop() = 0;

  // Best effort zero-rate command for error paths and destructors: never throws, returns within
  // the implementation's documented time bound even when the link is gone (it tries one bounded
  // reconnect). The table's own watchdog is the second line of defence.
  virtual void SafeStop() noexcept = 0;

  // Closes the link without commanding anything. Never throws.
  virtual void Disconnect() noexcept = 0;
};

}  // namespace hrgbench::hw
