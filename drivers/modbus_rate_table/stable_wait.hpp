#pragma once
// The "at a stable rate" decision, kept apart from any transport so it can be tested with a
// ManualClock and scripted statuses: the table's rate-stable bit AND |measured - target| within
// tolerance AND no fault (nor e-stop) bit, all continuously for a dwell window. The table's own bit
// alone is not trusted: its tolerance is the vendor's, not the experiment's.

#include <cstdint>
#include <expected>
#include <functional>

#include "hrgbench/hw/clock.hpp"
#include "hrgbench/hw/rate_table.hpp"

namespace hrgbench::drivers::modbus_rate_table {

class StableDetector {
 public:
  StableDetector(double tolerance_rad_s, std::int64_t dwell_ns) noexcept
      : tolerance_rad_s_(tolerance_rad_s), dwell_ns_(dwell_ns) {}

  // Feeds one status (its t_ns is the time base). True once every condition has held in every
  // status fed since a time at least dwell_ns before status.t_ns. A single failing status restarts
  // the window. Real-time safe.
  bool Update(const hw::RateTableStatus& status, double target_rate_rad_s) noexcept;
  void Reset() noexcept { holding_ = false; }

  // True when this one status meets the conditions (without the dwell).
  bool ConditionsHold(const hw::RateTableStatus& status, double target_rate_rad_s) const noexcept;

 private:
  double tolerance_rad_s_;
  std::int64_t dwell_ns_;
  bool holding_ = false;
  std::int64_t since_ns_ = 0;
};

using StatusReader = std::function<std::expected<hw::RateTableStatus, hw::RateTableError>()>;

// Polls `read` every criteria.poll_period_s of `clock` until StableDetector says stable (returns
// that status), a status shows a fault or e-stop (kFaulted, with the fault name), `read` fails (its
// error), or criteria.timeout_s passes (kNotStable with the last measured rate).
// Not real-time safe; runs on the caller's thread.
std::expected<hw::RateTableStatus, hw::RateTableError> WaitForStableRate(
    const StatusReader& read, hw::Clock& clock, double target_rate_rad_s,
    const hw::StableCriteria& criteria);

}  // namespace hrgbench::drivers::modbus_rate_table
