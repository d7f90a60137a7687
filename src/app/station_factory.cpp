#include "app/station_factory.hpp"

#include <array>
#include <complex>

#include "gyro_can/gyro_can_device.hpp"
#include "modbus_rate_table/modbus_rate_table.hpp"
#include "sim/carrier_config.hpp"
#include "sim/simulated_station.hpp"
#include "socketcan/socket_can_bus.hpp"

namespace hrgbench::app {
namespace {

static_assert(bench::kMaxCanNode == drivers::gyro_can::kMaxNodeId,
              "the station loader accepts the node ids the protocol has");

std::string Where(const bench::StationConfig& config) { return config.file.string() + ": "; }

class SimulatedStationAdapter final : public Station {
 public:
  SimulatedStationAdapter(std::unique_ptr<drivers::sim_station::SimulatedStation> station,
                          const std::vector<const bench::FixturePosition*>& fitted,
                          const std::array<double, 5>& forcer_errors)
      : station_(std::move(station)), forcer_errors_(forcer_errors) {
    hardware_.table = &station_->table();
    hardware_.clock = &station_->clock();
    for (std::size_t i = 0; i < fitted.size(); ++i) {
      bench::UnitHardware unit;
      unit.gyro = &station_->gyro(i);
      unit.operating = &station_->operating_gyro(i);
      unit.monitor = &station_->monitor(i);
      unit.can_interface = fitted[i]->can_interface;
      unit.can_node = fitted[i]->can_node;
      unit.can_protocol = drivers::gyro_can::kProtocolVersion;
      unit.position = fitted[i]->name;
      unit.axis_sign = fitted[i]->inverted ? -1 : 1;
      hardware_.units.push_back(unit);
    }
  }
  bench::BenchHardware& hardware() override { return hardware_; }
  std::optional<nlohmann::json> simulation(std::size_t i) const override {
    const drivers::sim_station::SimulatedTruth truth = station_->truth(i);
    nlohmann::json j;
    j["generator"] =
        truth.carrier ? "hrgbench in-process simulated station (drivers/sim_station), "
                        "carrier-level resonator and electronics (delta, xi mapped from the "
                        "physical parameters; sigma is not a y-level parameter there)"
                      : "hrgbench in-process simulated station (drivers/sim_station), exact model";
    j["physics"] = truth.carrier ? "carrier" : "slow";
    j["delta"] = std::vector<double>(truth.delta.data(), truth.delta.data() + 6);
    j["xi"] = std::vector<double>(truth.xi.data(), truth.xi.data() + 4);
    j["sigma"] = truth.sigma;
    j["seed"] = truth.seed;
    j["earth_rate_rad_s"] = truth.earth_rate_rad_s;
    // What the operating mode acts through (not seen by free runs; the tuning's refinement sees
    // it): β1, β2, β3, β4, b.
    if (!truth.carrier)
      j["forcer_errors"] = std::vector<double>(forcer_errors_.begin(), forcer_errors_.end());
    return j;
  }

 private:
  std::unique_ptr<drivers::sim_station::SimulatedStation> station_;
  std::array<double, 5> forcer_errors_;
  bench::BenchHardware hardware_;
};

class RealStation final : public Station {
 public:
  bench::BenchHardware& hardware() override { return hardware_; }
  std::optional<nlohmann::json> simulation(std::size_t) const override { return std::nullopt; }

  // One unit's link: its bus, the tap on it, the driver.
  struct UnitLink {
    std::unique_ptr<drivers::socketcan::SocketCanBus> bus;
    std::unique_ptr<drivers::socketcan::SocketCanBus> monitor;
    std::unique_ptr<drivers::gyro_can::GyroCanDevice> gyro;
  };

  hw::SteadyClock clock;
  std::vector<UnitLink> units;
  std::unique_ptr<drivers::modbus_rate_table::ModbusRateTable> table;
  bench::BenchHardware hardware_;
};

// One simulated unit: a fixture position's [simulated] (the station's with its own keys).
drivers::sim::GyroSimOptions MapSimulatedUnit(const bench::SimulatedStationConfig& sim) {
  drivers::sim::GyroSimOptions o;
  if (sim.physics == bench::SimulatedPhysics::kCarrier) {
    o.physics = drivers::sim::GyroPhysics::kCarrier;
    o.carrier = drivers::sim::CarrierOptionsFrom(sim.carrier);
  }
  o.delta = sim.delta;
  o.xi = sim.xi;
  // F = I + β1·σz + β4·σx − i·(β2·σz + β3·σx) + b·J (config/station_config.hpp forcer_errors).
  const auto& [beta1, beta2, beta3, beta4, b] = sim.forcer_errors;
  const std::complex<double> gain(beta1, -beta2), angle(beta4, -beta3);
  o.forcer_gain = Eigen::Matrix2cd::Identity();
  o.forcer_gain(0, 0) += gain;
  o.forcer_gain(1, 1) -= gain;
  o.forcer_gain(0, 1) += angle - b;
  o.forcer_gain(1, 0) += angle + b;
  o.sigma = sim.sigma;
  o.seed = sim.seed;
  o.excite_time_s = sim.excite_time_s;
  o.resonant_frequency_hz = sim.resonant_frequency_hz;
  o.temperature_c = sim.temperature_c;
  o.temperature_drift_c_per_s = sim.temperature_drift_c_per_s;
  const bench::SimulatedFaults& f = sim.faults;
  if (f.gyro_stall_after_samples) o.faults.stall_after_samples = *f.gyro_stall_after_samples;
  o.faults.stall_from_run = static_cast<std::uint64_t>(f.gyro_stall_from_run);
  if (f.gyro_bus_off_after_samples) o.faults.bus_off_after_samples = *f.gyro_bus_off_after_samples;
  o.faults.drop_every_nth_frame = static_cast<std::uint32_t>(f.gyro_drop_every_nth_sample);
  o.faults.never_ready = f.gyro_never_ready;
  return o;
}

drivers::sim_station::SimulatedStationOptions MapSimulated(const bench::StationConfig& config) {
  const bench::SimulatedStationConfig& sim = config.simulated;
  drivers::sim_station::SimulatedStationOptions o;
  o.faster_than_real_time = sim.faster_than_real_time;
  o.time_scale = sim.time_scale;
  o.units.clear();
  for (const bench::FixturePosition* position : bench::FittedPositions(config)) {
    drivers::sim::GyroSimOptions gyro =
        MapSimulatedUnit(bench::PositionSimulated(config, *position));
    gyro.node = static_cast<drivers::gyro_can::NodeId>(position->can_node);
    // Positions naming one interface share its in-process bus.
    o.units.push_back({gyro, position->inverted, position->can_interface});
  }
  o.earth_rate_rad_s = bench::EarthRateOnAxisRadS(config.site);
  o.table_physics.settle_time_constant_s = sim.table_settle_time_constant_s;
  o.table_physics.noise_rad_s = sim.table_noise_rad_s;
  o.table_physics.encoder_counts_per_rev =
      static_cast<std::uint32_t>(sim.table_encoder_counts_per_rev);
  o.table_physics.encoder_noise_rad = sim.table_encoder_noise_rad;
  o.table_physics.stable_tolerance_rad_s = sim.table_stable_tolerance_rad_s;
  o.table_physics.stable_hold_s = sim.table_stable_hold_s;
  o.table_physics.seed = sim.seed + 1000;
  o.table_physics.accel_limit_rad_s2 = config.table.accel_rad_s2;
  o.table.limits.max_rate_rad_s = config.table.max_rate_rad_s;
  o.table.limits.max_accel_rad_s2 = config.table.max_accel_rad_s2;
  o.table.accel_limit_rad_s2 = config.table.accel_rad_s2;
  o.table.watchdog_timeout_ms = static_cast<std::uint16_t>(config.table.watchdog_ms);
  o.table.heartbeat_period_ms = config.table.heartbeat_period_ms;
  o.table.response_timeout_ms = config.table.response_timeout_ms;
  o.table.safe_stop_budget_ms = config.table.safe_stop_budget_ms;
  o.gyro_link.ack_timeout_ns = config.gyro.ack_timeout_ms * 1'000'000;
  o.gyro_link.command_attempts = static_cast<int>(config.gyro.command_attempts);
  o.gyro_link.status_poll_ns = config.gyro.status_poll_ms * 1'000'000;
  // The transport the plan was checked against is the one the simulated station uses.
  o.can_fd = config.gyro.fd;
  // The in-process bus runs at the rates the plan was judged at (hrg-bench check's bus load).
  o.can_bit_rate_bps = config.gyro.bitrate;
  o.can_data_bit_rate_bps = config.gyro.data_bitrate;
  o.gyro_link.prefer_fd = config.gyro.fd;
  const bench::SimulatedFaults& f = sim.faults;
  o.table.faults.never_stable = f.table_never_stable;
  if (f.table_fault_after_s) o.table.faults.fault_after_s = *f.table_fault_after_s;
  if (f.table_unresponsive_after_s)
    o.table.faults.unresponsive_after_s = *f.table_unresponsive_after_s;
  return o;
}

std::expected<std::unique_ptr<Station>, std::string> OpenSimulated(
    const bench::StationConfig& config) {
  auto station = drivers::sim_station::SimulatedStation::Create(MapSimulated(config));
  if (!station) return std::unexpected(Where(config) + "simulated station: " + station.error());
  if (auto connected = (*station)->table().Connect(); !connected)
    return std::unexpected(Where(config) + "simulated table: " + connected.error().ToString());
  return std::make_unique<SimulatedStationAdapter>(
      std::move(*station), bench::FittedPositions(config), config.simulated.forcer_errors);
}

std::expected<std::unique_ptr<Station>, std::string> OpenReal(const bench::StationConfig& config) {
  auto station = std::make_unique<RealStation>();
  drivers::socketcan::SocketCanOptions can;
  can.fd = config.gyro.fd;
  drivers::gyro_can::GyroCanDeviceConfig link;
  link.clock = &station->clock;
  link.ack_timeout_ns = config.gyro.ack_timeout_ms * 1'000'000;
  link.command_attempts = static_cast<int>(config.gyro.command_attempts);
  link.status_poll_ns = config.gyro.status_poll_ms * 1'000'000;
  link.prefer_fd = config.gyro.fd;
  const std::vector<const bench::FixturePosition*> fitted = bench::FittedPositions(config);
  for (const bench::FixturePosition* position : fitted) {
    // "gyro CAN" for a station of one unit, as before; the position's name on a fixture.
    const std::string unit =
        fitted.size() == 1 ? std::string() : "position " + position->name + ": ";
    RealStation::UnitLink unit_link;
    auto bus = drivers::socketcan::SocketCanBus::Open(position->can_interface, can);
    if (!bus) return std::unexpected(Where(config) + unit + "gyro CAN: " + bus.error());
    unit_link.bus = std::move(*bus);
    auto monitor = drivers::socketcan::SocketCanBus::Open(position->can_interface, can);
    if (!monitor) return std::unexpected(Where(config) + unit + "CAN tap: " + monitor.error());
    unit_link.monitor = std::move(*monitor);
    // The tap records this unit's node: on a shared bus each unit's log is its own traffic.
    const std::array<hw::CanFilter, 1> own_node = {drivers::gyro_can::NodeTrafficFilter(
        static_cast<drivers::gyro_can::NodeId>(position->can_node))};
    if (unit_link.monitor->SetFilters(own_node) != hw::CanStatus::kOk)
      return std::unexpected(Where(config) + unit + "CAN tap: its filter was refused");
    link.node = static_cast<drivers::gyro_can::NodeId>(position->can_node);
    auto gyro = drivers::gyro_can::GyroCanDevice::Create(*unit_link.bus, link);
    if (!gyro) return std::unexpected(Where(config) + unit + "gyro: " + gyro.error().ToString());
    unit_link.gyro = std::move(*gyro);
    station->units.push_back(std::move(unit_link));
  }

  drivers::modbus_rate_table::ModbusRateTableConfig table;
  const bench::TableLinkConfig& t = config.table;
  table.transport = t.transport == bench::TableTransport::kTcp
                        ? drivers::modbus_rate_table::ModbusTransport::kTcp
                        : drivers::modbus_rate_table::ModbusTransport::kRtu;
  table.host = t.host;
  table.port = static_cast<int>(t.port);
  table.serial_device = t.device;
  table.baud = static_cast<int>(t.baud);
  table.parity = t.parity;
  table.data_bits = static_cast<int>(t.data_bits);
  table.stop_bits = static_cast<int>(t.stop_bits);
  table.unit_id = static_cast<int>(t.unit_id);
  table.response_timeout_ms = static_cast<int>(t.response_timeout_ms);
  table.byte_timeout_ms = static_cast<int>(t.byte_timeout_ms);
  table.transaction_attempts = static_cast<int>(t.transaction_attempts);
  table.connect_attempts = static_cast<int>(t.connect_attempts);
  table.reconnect_backoff_ms = static_cast<int>(t.reconnect_backoff_ms);
  table.watchdog_timeout_ms = static_cast<int>(t.watchdog_ms);
  table.heartbeat_period_ms = static_cast<int>(t.heartbeat_period_ms);
  table.accel_limit_rad_s2 = t.accel_rad_s2;
  table.limits.max_rate_rad_s = t.max_rate_rad_s;
  table.limits.max_accel_rad_s2 = t.max_accel_rad_s2;
  table.safe_stop_budget_ms = static_cast<int>(t.safe_stop_budget_ms);
  station->table =
      std::make_unique<drivers::modbus_rate_table::ModbusRateTable>(table, station->clock);
  if (auto connected = station->table->Connect(); !connected)
    return std::unexpected(Where(config) + "rate table (" + table.Describe() +
                           "): " + connected.error().ToString());
  station->hardware_.table = station->table.get();
  station->hardware_.clock = &station->clock;
  for (std::size_t i = 0; i < fitted.size(); ++i) {
    bench::UnitHardware unit;
    unit.gyro = station->units[i].gyro.get();
    unit.operating = station->units[i].gyro.get();
    unit.monitor = station->units[i].monitor.get();
    unit.monitor_stamps_on_bench_clock = false;  // SocketCAN: software = realtime
    unit.can_interface = fitted[i]->can_interface;
    unit.can_node = fitted[i]->can_node;
    unit.can_protocol = drivers::gyro_can::kProtocolVersion;
    unit.position = fitted[i]->name;
    unit.axis_sign = fitted[i]->inverted ? -1 : 1;
    station->hardware_.units.push_back(unit);
  }
  return station;
}

}  // namespace

std::expected<std::unique_ptr<Station>, std::string> OpenStation(
    const bench::StationConfig& config) {
  return config.kind == bench::StationKind::kSimulated ? OpenSimulated(config) : OpenReal(config);
}

}  // namespace hrgbench::app
