#pragma once
// SimulatedStation: a whole bench station in one process, no hardware and no other program, built
// from the real protocol peers where they exist:
//
//   RateTable  = InProcessRateTable on a TablePhysics (the table simulator's physics)
//   Gyro i     = GyroCanDevice (the real gyro driver) --VirtualCanBus--> GyroSimNode (the
//                simulated electronics, protocol v2, node units[i].gyro.node), whose Ω is the
//                table physics' true rate plus the Earth-rate component: one per unit on the
//                table, each on its own bus or several on a shared one (units[i].bus), where
//                they contend for it at its bit timing and an overloaded bus loses frames at
//                their transmit queues
//   Monitor i  = a node on unit i's bus that receives every frame of unit i's node id, both
//                directions: the raw-frame tap the bench records (candump log)
//   Clock      = one clock for all of them (see SimulatedStationOptions for the three modes)
//
// Faster than real time (VirtualTimeClock, see virtual_time_clock.hpp): the bench's threads block
// in the drivers' waits as usual; simulated time advances when all of them wait, the gyro node is
// stepped by the clock at its own events, and receivers are woken by every frame. 100 s of 1 kHz
// samples cost the CPU time of producing and decoding them, a few hundred ms.
// Real time: SteadyClock, the gyro node runs in its own thread (GyroSimNode::Run), the bus wakes
// receivers with condition variables: the same code paths as the cross-process station.
//
// Ownership: the station owns everything; the references it hands out live as long as it does.
// Destroying it stops the gyro node's thread; it commands nothing (call SafeStop first).
// Threads: table() belongs to one thread (the sequencer), each gyro(i) to one (its capture
// thread), each monitor(i) to one reader; clock() is shared. See each interface's header.
// Failure modes: the options' gyro.faults and table.faults; bus() for bus-level injection
// (DropNext, CorruptNext, SetBusOff); InjectGyroFaults at run time.

#include <atomic>
#include <expected>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "can_virtual/virtual_can_bus.hpp"
#include "gyro_can/gyro_can_device.hpp"
#include "hrgbench/hw/can_bus.hpp"
#include "hrgbench/hw/clock.hpp"
#include "hrgbench/hw/gyro_electronics.hpp"
#include "hrgbench/hw/operating_gyro.hpp"
#include "hrgbench/hw/rate_table.hpp"
#include "sim/clocked_can_endpoint.hpp"
#include "sim/gyro_sim_node.hpp"
#include "sim/in_process_rate_table.hpp"
#include "sim/simulated_station_options.hpp"
#include "sim/table_physics.hpp"
#include "sim/virtual_time_clock.hpp"

namespace hrgbench::drivers::sim_station {

class SimulatedStation {
 public:
  // Validates the options (the message names the field), builds the parts, and in real time
  // starts the gyro node's thread. The table is not connected yet (RateTable::Connect).
  static std::expected<std::unique_ptr<SimulatedStation>, std::string> Create(
      const SimulatedStationOptions& options);
  ~SimulatedStation();
  SimulatedStation(const SimulatedStation&) = delete;
  SimulatedStation& operator=(const SimulatedStation&) = delete;

  // Unit `i` is options().units[i]; i < unit_count().
  std::size_t unit_count() const noexcept { return units_.size(); }
  hw::RateTable& table() noexcept { return *table_; }
  hw::GyroElectronics& gyro(std::size_t i = 0) noexcept { return *units_[i].device; }
  // The same electronics as a gyro: their parameter block and angle output (same thread as
  // gyro(i)).
  hw::OperatingGyro& operating_gyro(std::size_t i = 0) noexcept { return *units_[i].device; }
  hw::Clock& clock() noexcept { return *clock_; }
  // The raw-frame tap: every frame of unit i's node id on its bus, host's and electronics', in bus
  // order, stamped on the station's clock. One reader thread. Frames not read pile up to
  // monitor_queue_frames.
  hw::CanBus& monitor(std::size_t i = 0) noexcept { return *units_[i].monitor_bus; }

  SimulatedTruth truth(std::size_t i = 0) const;
  const SimulatedStationOptions& options() const noexcept { return options_; }
  bool faster_than_real_time() const noexcept { return virtual_clock_ != nullptr; }

  // The concrete parts, for tests and the app's diagnostics.
  InProcessRateTable& in_process_table() noexcept { return *table_; }
  gyro_can::GyroCanDevice& gyro_device(std::size_t i = 0) noexcept { return *units_[i].device; }
  // Unit i's bus (shared with the units that name the same bus).
  can_virtual::VirtualCanBus& bus(std::size_t i = 0) noexcept { return *units_[i].bus; }
  VirtualTimeClock* virtual_clock() noexcept { return virtual_clock_.get(); }  // null: real time
  // The simulated electronics' counters. In real time they are read racily (diagnostics only).
  sim::GyroSimStatistics gyro_sim_statistics(std::size_t i = 0) const;

  // Changes the simulated electronics' failure modes while running, safely with respect to the
  // thread that drives the node. False in real time (the node's thread owns them; set them in
  // the options instead).
  bool InjectGyroFaults(const std::function<void(sim::GyroSimFaults&)>& change, std::size_t i = 0);

 private:
  // One unit: its bus, the three nodes on it, the driver. Declaration order is construction
  // order.
  struct Unit {
    can_virtual::VirtualCanBus* bus = nullptr;  // in buses_, perhaps shared with other units
    std::unique_ptr<can_virtual::VirtualCanEndpoint> host_endpoint;
    std::unique_ptr<can_virtual::VirtualCanEndpoint> node_endpoint;
    std::unique_ptr<can_virtual::VirtualCanEndpoint> monitor_endpoint;
    std::unique_ptr<ClockedCanEndpoint> host_clocked;     // faster than real time only
    std::unique_ptr<ClockedCanEndpoint> monitor_clocked;  // faster than real time only
    hw::CanBus* host_bus = nullptr;
    hw::CanBus* monitor_bus = nullptr;
    std::unique_ptr<sim::GyroSimNode> node;
    std::unique_ptr<gyro_can::GyroCanDevice> device;
    std::thread node_thread;  // real time only
  };

  explicit SimulatedStation(const SimulatedStationOptions& options);
  std::expected<void, std::string> Build();
  std::expected<void, std::string> BuildUnit(const SimulatedUnitOptions& options, Unit& unit);

  SimulatedStationOptions options_;
  // Declaration order is construction order; destruction runs backwards (the node thread is
  // stopped in the destructor's body first).
  std::unique_ptr<VirtualTimeClock> virtual_clock_;
  hw::SteadyClock steady_clock_;
  hw::Clock* clock_ = nullptr;
  std::unique_ptr<sim::TablePhysics> physics_;
  std::unique_ptr<InProcessRateTable> table_;
  std::vector<std::unique_ptr<can_virtual::VirtualCanBus>> buses_;
  std::vector<std::string> bus_names_;  // buses_[k]'s SimulatedUnitOptions::bus ("" unshared)
  std::vector<Unit> units_;
  std::atomic<bool> stop_node_{false};
};

}  // namespace hrgbench::drivers::sim_station
