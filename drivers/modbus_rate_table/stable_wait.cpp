#include "modbus_rate_table/stable_wait.hpp"

#include <cmath>
#include <sstream>

namespace hrgbench::drivers::modbus_rate_table {

using hw::SecondsToNs;

bool StableDetector::ConditionsHold(const hw::RateTableStatus& status,
                                    double target_rate_rad_s) const noexcept {
  return status.rate_stable && !status.fault && !status.estop &&
         std::abs(status.measured_rate_rad_s - target_rate_rad_s) <= tolerance_rad_s_;
}

bool StableDetector::Update(const hw::RateTableStatus& status, double target_rate_rad_s) noexcept {
  if (!ConditionsHold(status, target_rate_rad_s)) {
    holding_ = false;
    return false;
  }
  if (!holding_) {
    holding_ = true;
    since_ns_ = status.t_ns;
  }
  return status.t_ns - since_ns_ >= dwell_ns_;
}

std::expected<hw::RateTableStatus, hw::RateTableError> WaitForStableRate(
    const StatusReader& read, hw::Clock& clock, double target_rate_rad_s,
    const hw::StableCriteria& criteria) {
  std::string why;
  if (!criteria.IsValid(&why)) {
    return std::unexpected(hw::RateTableError{hw::RateTableErrorCode::kInvalidConfig, why});
  }
  StableDetector detector(criteria.tolerance_rad_s, SecondsToNs(criteria.dwell_s));
  const std::int64_t start_ns = clock.NowNs();
  const std::int64_t timeout_ns = SecondsToNs(criteria.timeout_s);
  const std::int64_t poll_ns = SecondsToNs(criteria.poll_period_s);
  while (true) {
    auto status = read();
    if (!status) return std::unexpected(status.error());
    if (status->fault || status->estop) {
      return std::unexpected(hw::RateTableError{
          hw::RateTableErrorCode::kFaulted,
          "table reports fault '" + hw::RateTableFaultName(status->fault_code) + "'" +
              (status->estop ? " (e-stop active)" : "") + " while waiting for a stable rate"});
    }
    if (detector.Update(*status, target_rate_rad_s)) return *status;
    if (clock.NowNs() - start_ns >= timeout_ns) {
      std::ostringstream os;
      os << "rate not stable within " << criteria.timeout_s << " s: target " << target_rate_rad_s
         << " rad/s, measured " << status->measured_rate_rad_s << " rad/s, tolerance "
         << criteria.tolerance_rad_s << " rad/s, dwell " << criteria.dwell_s
         << " s, table stable bit " << (status->rate_stable ? 1 : 0);
      return std::unexpected(hw::RateTableError{hw::RateTableErrorCode::kNotStable, os.str()});
    }
    clock.SleepForNs(poll_ns);
  }
}

}  // namespace hrgbench::drivers::modbus_rate_table
