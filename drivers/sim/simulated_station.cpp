#include "sim/simulated_station.hpp"

#include <algorithm>
#include <array>

#include "hrgbench/estimator/physical_parameters.hpp"
#include "hrgbench/estimator/pickoff_frame.hpp"
#include "sim/carrier_pickoff.hpp"

namespace hrgbench::drivers::sim_station {

namespace can_virtual = drivers::can_virtual;

std::expected<std::unique_ptr<SimulatedStation>, std::string> SimulatedStation::Create(
    const SimulatedStationOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) return std::unexpected("simulated station: " + why);
  std::unique_ptr<SimulatedStation> station(new SimulatedStation(options));
  if (auto built = station->Build(); !built) return std::unexpected(built.error());
  return station;
}

SimulatedStation::SimulatedStation(const SimulatedStationOptions& options) : options_(options) {}

std::expected<void, std::string> SimulatedStation::Build() {
  const bool real_time = !options_.faster_than_real_time && options_.time_scale == 1.0;
  if (real_time) {
    clock_ = &steady_clock_;
  } else {
    VirtualTimeClockOptions clock_options;
    clock_options.time_scale = options_.faster_than_real_time ? 0.0 : options_.time_scale;
    clock_options.park_after_wall_ns = options_.park_after_wall_ns;
    clock_options.output_lookahead_ns = options_.output_lookahead_ns;
    virtual_clock_ = std::make_unique<VirtualTimeClock>(clock_options);
    clock_ = virtual_clock_.get();
  }

  physics_ = std::make_unique<sim::TablePhysics>(options_.table_physics, *clock_);
  table_ = std::make_unique<InProcessRateTable>(options_.table, *physics_, *clock_);

  units_.resize(options_.units.size());
  for (std::size_t i = 0; i < units_.size(); ++i) {
    if (auto built = BuildUnit(options_.units[i], units_[i]); !built)
      return std::unexpected(units_.size() == 1
                                 ? built.error()
                                 : "unit " + std::to_string(i + 1) + ": " + built.error());
  }
  return {};
}

std::expected<void, std::string> SimulatedStation::BuildUnit(const SimulatedUnitOptions& options,
                                                             Unit& unit) {
  const auto shared = std::find(bus_names_.begin(), bus_names_.end(), options.bus);
  if (!options.bus.empty() && shared != bus_names_.end()) {
    unit.bus = buses_[static_cast<std::size_t>(shared - bus_names_.begin())].get();
  } else {
    can_virtual::VirtualCanBusOptions bus_options;
    bus_options.nominal_bit_rate_bps = options_.can_bit_rate_bps;
    bus_options.stuff_bits = true;  // as full as a real bus: what several units on one cost
    bus_options.fd = options_.can_fd;
    bus_options.data_bit_rate_bps = options_.can_fd ? options_.can_data_bit_rate_bps : 0;
    // Real time: nullptr = the bus's own steady clock with condition-variable wake-ups (the same
    // time base as steady_clock_). Virtual time: the station's clock, for stamps and bit timing.
    bus_options.clock = virtual_clock_.get();
    auto bus = can_virtual::VirtualCanBus::Create(bus_options);
    if (!bus) return std::unexpected("simulated station: " + bus.error());
    buses_.push_back(std::move(*bus));
    bus_names_.push_back(options.bus);
    unit.bus = buses_.back().get();
  }
  unit.host_endpoint = unit.bus->CreateEndpoint({.queue_capacity = options_.host_queue_frames});
  // In real time (the steady clock) a simulator thread the machine descheduled sends the samples
  // it owes in one burst that real electronics would have spread over the stall; the queue then
  // absorbs a stall of ~0.5 s at 1 kHz instead of losing samples no unit would lose (the real-time
  // test lost 6 of 500 at load 5). On virtual time the node never stalls: the queue is the one set.
  constexpr std::size_t kRealTimeBurstFrames = 1024;
  const std::size_t transmit_queue =
      clock_ == &steady_clock_ && options_.node_transmit_queue_frames != 0
          ? std::max(options_.node_transmit_queue_frames, kRealTimeBurstFrames)
          : options_.node_transmit_queue_frames;
  unit.node_endpoint = unit.bus->CreateEndpoint(
      {.receive_own_frames = false, .queue_capacity = 0, .transmit_queue_frames = transmit_queue});
  unit.monitor_endpoint =
      unit.bus->CreateEndpoint({.queue_capacity = options_.monitor_queue_frames});
  // The tap records this unit's node only: on a shared bus each unit's log is its own traffic.
  const std::array<hw::CanFilter, 1> own_node = {gyro_can::NodeTrafficFilter(options.gyro.node)};
  if (unit.monitor_endpoint->SetFilters(own_node) != hw::CanStatus::kOk)
    return std::unexpected("simulated station: the tap's filter was refused");
  if (virtual_clock_) {
    unit.host_clocked =
        std::make_unique<ClockedCanEndpoint>(*unit.bus, *unit.host_endpoint, *virtual_clock_);
    unit.monitor_clocked =
        std::make_unique<ClockedCanEndpoint>(*unit.bus, *unit.monitor_endpoint, *virtual_clock_);
    unit.host_bus = unit.host_clocked.get();
    unit.monitor_bus = unit.monitor_clocked.get();
  } else {
    unit.host_bus = unit.host_endpoint.get();
    unit.monitor_bus = unit.monitor_endpoint.get();
  }

  InProcessRateTable* table = table_.get();
  const double earth_rate_rad_s = options_.earth_rate_rad_s;
  const double axis_sign = options.inverted ? -1.0 : 1.0;
  can_virtual::VirtualCanBus* shorted_bus = unit.bus;
  unit.node = std::make_unique<sim::GyroSimNode>(
      *unit.node_endpoint, *clock_, options.gyro,
      [table, earth_rate_rad_s, axis_sign] {
        return axis_sign * (table->SenseTrueRateRadS() + earth_rate_rad_s);
      },
      [shorted_bus] { shorted_bus->SetBusOff(true); });

  gyro_can::GyroCanDeviceConfig link = options_.gyro_link;
  link.clock = clock_;
  link.node = options.gyro.node;
  auto device = gyro_can::GyroCanDevice::Create(*unit.host_bus, link);
  if (!device)
    return std::unexpected("simulated station: gyro driver: " + device.error().ToString());
  unit.device = std::move(*device);

  if (virtual_clock_) {
    virtual_clock_->AddParticipant(unit.node.get());
  } else {
    sim::GyroSimNode* node = unit.node.get();
    unit.node_thread = std::thread([this, node] { node->Run(stop_node_); });
  }
  return {};
}

SimulatedStation::~SimulatedStation() {
  stop_node_.store(true, std::memory_order_release);
  for (Unit& unit : units_) {
    if (unit.node_thread.joinable()) unit.node_thread.join();  // Run sees `stop` within 50 ms
    if (virtual_clock_ && unit.node) virtual_clock_->RemoveParticipant(unit.node.get());
  }
}

SimulatedTruth SimulatedStation::truth(std::size_t i) const {
  const sim::GyroSimOptions& gyro = options_.units[i].gyro;
  // What the unit senses of the Earth's rate: on its own axis.
  const double earth_rate_rad_s =
      (options_.units[i].inverted ? -1.0 : 1.0) * options_.earth_rate_rad_s;
  if (gyro.physics == sim::GyroPhysics::kCarrier) {
    const sim::CarrierOptions& c = gyro.carrier;
    // What the slow model should find: δ in the model's frame with the housing's temperature
    // drift's decay (at the start temperature), ξ the pick-off's in that frame with the split's
    // second-order mixing (estimator/pickoff_frame.hpp). The pick-off's H is the simulator's own.
    const double relative_rate = c.frequency_temperature_coefficient_per_c *
                                 gyro.temperature_drift_c_per_s /
                                 (1.0 + c.frequency_temperature_coefficient_per_c *
                                            (gyro.temperature_c - c.reference_temperature_c));
    const sim::CarrierPickoff pickoff(c.pickoff, c.resonator.frequency_hz);
    const estimator::SlowModelTruth seen =
        estimator::SlowModelSeenOnUnit(c.resonator, pickoff.carrier_gain(), relative_rate);
    return {true, seen.delta, seen.xi, 0.0, gyro.seed, earth_rate_rad_s};
  }
  return {false, gyro.delta, gyro.xi, gyro.sigma, gyro.seed, earth_rate_rad_s};
}

sim::GyroSimStatistics SimulatedStation::gyro_sim_statistics(std::size_t i) const {
  sim::GyroSimStatistics statistics;
  const sim::GyroSimNode& node = *units_[i].node;
  if (virtual_clock_) {
    virtual_clock_->WithParticipantsLocked([&] { statistics = node.Statistics(); });
  } else {
    statistics = node.Statistics();
  }
  return statistics;
}

bool SimulatedStation::InjectGyroFaults(const std::function<void(sim::GyroSimFaults&)>& change,
                                        std::size_t i) {
  if (!virtual_clock_) return false;
  sim::GyroSimNode& node = *units_[i].node;
  virtual_clock_->WithParticipantsLocked([&] { change(node.faults()); });
  return true;
}

}  // namespace hrgbench::drivers::sim_station
