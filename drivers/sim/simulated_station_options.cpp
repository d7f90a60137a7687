#include "sim/simulated_station_options.hpp"

#include <cmath>

namespace hrgbench::drivers::sim_station {

bool SimulatedStationOptions::IsValid(std::string* why) const {
  const auto fail = [why](std::string message) {
    if (why != nullptr) *why = std::move(message);
    return false;
  };
  if (!faster_than_real_time && !(std::isfinite(time_scale) && time_scale > 0.0)) {
    return fail("time_scale must be finite and > 0, got " + std::to_string(time_scale));
  }
  if (park_after_wall_ns <= 0) return fail("park_after_wall_ns must be > 0");
  if (output_lookahead_ns < 0) return fail("output_lookahead_ns must be >= 0");
  if (!std::isfinite(earth_rate_rad_s) || std::abs(earth_rate_rad_s) > 1e-3) {
    return fail("earth_rate_rad_s must be finite and within +-1e-3 rad/s, got " +
                std::to_string(earth_rate_rad_s));
  }
  std::string part;
  if (units.empty() || units.size() > kMaxSimulatedUnits)
    return fail("units: between 1 and " + std::to_string(kMaxSimulatedUnits) + " units, got " +
                std::to_string(units.size()));
  for (std::size_t i = 0; i < units.size(); ++i) {
    if (!units[i].gyro.IsValid(&part))
      return fail("units[" + std::to_string(i) + "].gyro: " + part);
    for (std::size_t j = 0; j < i; ++j) {
      if (!units[i].bus.empty() && units[j].bus == units[i].bus &&
          units[j].gyro.node == units[i].gyro.node) {
        return fail("units[" + std::to_string(j) + "] and units[" + std::to_string(i) +
                    "] are both node " + std::to_string(units[i].gyro.node) + " on bus '" +
                    units[i].bus + "': units on one bus need distinct node ids");
      }
    }
  }
  if (!table_physics.IsValid(&part)) return fail("table_physics: " + part);
  if (!table.IsValid(&part)) return fail("table: " + part);
  gyro_can::GyroCanDeviceConfig link = gyro_link;
  hw::SteadyClock placeholder;  // the station supplies its clock; validate the rest
  link.clock = &placeholder;
  if (!link.IsValid(&part)) return fail("gyro_link: " + part);
  if (can_bit_rate_bps < 0) return fail("can_bit_rate_bps must be >= 0 (0 = untimed)");
  if (host_queue_frames == 0 || monitor_queue_frames == 0) {
    return fail("host_queue_frames and monitor_queue_frames must be >= 1");
  }
  return true;
}

}  // namespace hrgbench::drivers::sim_station
