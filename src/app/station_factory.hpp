#pragma once
// The one place that picks concrete drivers (STYLE: app → bench → interfaces ← drivers): a station
// config becomes the hardware a bench session runs on.
//   simulated: the in-process simulated station (drivers/sim_station): the real gyro driver and
//   protocol on
//              a virtual CAN bus with the simulated electronics, the table physics behind an
//              in-process RateTable; faster than real time or paced.
//   real:      per fitted position, SocketCAN on its interface (a second socket taps every frame
//              for the candump log) and a GyroCanDevice; the Modbus rate table (TCP or RTU).

#include <expected>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "hrgbench/bench/sequencer/sequencer.hpp"
#include "hrgbench/config/station_config.hpp"

namespace hrgbench::app {

class Station {
 public:
  virtual ~Station() = default;
  // The table and one unit per fitted fixture position, in the station's order.
  virtual bench::BenchHardware& hardware() = 0;
  // Truth of the simulated unit `i` for its record ("simulation"); nullopt for real hardware.
  virtual std::optional<nlohmann::json> simulation(std::size_t i = 0) const = 0;
};

// Builds and connects the station (the table is connected; the gyro driver is created). Errors name
// the config file and what failed.
std::expected<std::unique_ptr<Station>, std::string> OpenStation(
    const bench::StationConfig& config);

}  // namespace hrgbench::app
