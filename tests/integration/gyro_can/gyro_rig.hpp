#pragma once
// A host and the simulated HRG electronics on one in-process VirtualCanBus, driven by a
// SimulationClock: the device's waits in Receive advance simulated time, during which the
// GyroSimNode answers and streams. Deterministic, single-threaded, faster than real time.

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "can_virtual/virtual_can_bus.hpp"
#include "gyro_can/gyro_can_device.hpp"
#include "sim/gyro_sim_node.hpp"
#include "sim/simulation_clock.hpp"

namespace hrgbench::testing {

struct GyroRigOptions {
  drivers::sim::GyroSimOptions sim;
  drivers::gyro_can::GyroCanDeviceConfig device;  // clock is filled in by the rig
  std::int64_t bit_rate_bps = 1'000'000;          // 0: untimed bus
  bool fd_bus = false;
  double omega_rad_s = 0.3;
};

class GyroRig {
 public:
  explicit GyroRig(const GyroRigOptions& options) : omega_rad_s(options.omega_rad_s) {
    drivers::can_virtual::VirtualCanBusOptions bus_options;
    bus_options.nominal_bit_rate_bps = options.bit_rate_bps;
    bus_options.data_bit_rate_bps = options.fd_bus ? 5'000'000 : 0;
    bus_options.fd = options.fd_bus;
    bus_options.clock = &clock;
    auto created = drivers::can_virtual::VirtualCanBus::Create(bus_options);
    EXPECT_TRUE(created.has_value());
    bus = std::move(*created);
    host_endpoint = bus->CreateEndpoint();
    sim_endpoint = bus->CreateEndpoint();
    node = std::make_unique<drivers::sim::GyroSimNode>(
        *sim_endpoint, clock, options.sim, [this] { return omega_rad_s; },
        [this] { bus->SetBusOff(true); });
    clock.AddParticipant(node.get());
    drivers::gyro_can::GyroCanDeviceConfig device_config = options.device;
    device_config.clock = &clock;
    auto made = drivers::gyro_can::GyroCanDevice::Create(*host_endpoint, device_config);
    EXPECT_TRUE(made.has_value()) << (made ? "" : made.error().ToString());
    device = std::move(*made);
  }
  ~GyroRig() { clock.RemoveParticipant(node.get()); }

  // Configure → Excite → WaitReady → Release; returns t0 (asserts on failure).
  std::int64_t StartRun(std::uint32_t rate_hz, const hw::WaveState& wave) {
    auto configured = device->Configure({rate_hz});
    EXPECT_TRUE(configured.has_value()) << configured.error().ToString();
    auto excited = device->Excite(wave);
    EXPECT_TRUE(excited.has_value()) << excited.error().ToString();
    auto ready = device->WaitReady(2'000'000'000);
    EXPECT_TRUE(ready.has_value()) << ready.error().ToString();
    auto t0 = device->Release();
    EXPECT_TRUE(t0.has_value()) << t0.error().ToString();
    return t0.value_or(0);
  }

  drivers::sim::SimulationClock clock;
  double omega_rad_s;
  std::unique_ptr<drivers::can_virtual::VirtualCanBus> bus;
  std::unique_ptr<drivers::can_virtual::VirtualCanEndpoint> host_endpoint;
  std::unique_ptr<drivers::can_virtual::VirtualCanEndpoint> sim_endpoint;
  std::unique_ptr<drivers::sim::GyroSimNode> node;
  std::unique_ptr<drivers::gyro_can::GyroCanDevice> device;
};

}  // namespace hrgbench::testing
