#pragma once
// Options of the in-process simulated station (SimulatedStation): how time runs, the truth the
// simulated gyro follows, the table's physics and driver settings, the CAN bus, and the failure
// modes of gyro and table. Plain data with in-class defaults, independent of the bench's config
// files: src/app maps bench::SimulatedStationConfig ([station] kind = "simulated") onto it.
//
// Time modes (the two flags map one to one onto the station config's keys):
//   faster_than_real_time = true          VirtualTimeClock, as fast as the CPU allows (CI)
//   faster_than_real_time = false, time_scale = 1
//                                         real time: SteadyClock, the gyro node in its own thread,
//                                         waits woken by condition variables (the real-time paths)
//   faster_than_real_time = false, time_scale = s != 1
//                                         VirtualTimeClock paced at s simulated s per wall s

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "gyro_can/gyro_can_device.hpp"
#include "sim/gyro_sim_options.hpp"
#include "sim/in_process_rate_table.hpp"
#include "sim/table_physics.hpp"

namespace hrgbench::drivers::sim_station {

// A fixture carries at most this many units (the station config's bound too).
inline constexpr std::size_t kMaxSimulatedUnits = 16;

// One simulated unit on the table.
struct SimulatedUnitOptions {
  // Its electronics: the truth (δ, ξ, σ, seed), their behaviour, their failure modes (faults).
  sim::GyroSimOptions gyro;
  // Mounted with its sensitive axis against the table's axis: it senses −(table rate + the
  // Earth-rate component on the table's axis).
  bool inverted = false;
  // The in-process bus it is on: units with the same name share one bus (their electronics need
  // distinct gyro.node ids and contend for it at its bit timing); empty: a bus of its own.
  std::string bus;
};

struct SimulatedStationOptions {
  bool faster_than_real_time = true;
  double time_scale = 1.0;  // used only when !faster_than_real_time; > 0
  // VirtualTimeClock: a thread asleep off the clock this long (wall) stops holding time back (a
  // thread that is working or waiting for a CPU never does). 5 s: a thread asleep that long is
  // blocked, not briefly waiting for a lock; the cost of a long value is only felt by a thread
  // that blocks off the clock without detaching, which the bench does not do.
  std::int64_t park_after_wall_ns = 5'000'000'000;
  // VirtualTimeClock: how far time may run on past a frame before the thread it woke has handled
  // it (batching; see VirtualTimeClockOptions::output_lookahead_ns). 0: strictly conservative.
  std::int64_t output_lookahead_ns = 20'000'000;

  // Each unit on the table (one per fitted fixture position, on its own bus or sharing one: its
  // `bus`). Default: one
  // unit, the paper's experiment, noise-free; set its gyro.sigma for realism.
  std::vector<SimulatedUnitOptions> units{SimulatedUnitOptions{}};
  // Ω sensed by the gyro = the table's true rate + this Earth-rate component on the sensitive
  // axis (bench::EarthRateOnAxisRadS of the station's site), rad/s.
  double earth_rate_rad_s = 0.0;

  // The rate table: its physics (drivers/sim) and the in-process driver (limits, heartbeat,
  // watchdog, failure modes in table.faults).
  sim::TablePhysicsOptions table_physics;
  InProcessRateTableConfig table;

  // The host side of the gyro link (GyroCanDevice); its clock is the station's (ignored here).
  gyro_can::GyroCanDeviceConfig gyro_link;

  // Each unit's in-process CAN bus. 1 Mbit/s classic CAN: a frame takes its bit time, as on the
  // cable.
  std::int64_t can_bit_rate_bps = 1'000'000;
  bool can_fd = false;                             // FD bus; gyro_link.prefer_fd
  std::int64_t can_data_bit_rate_bps = 5'000'000;  // FD data phase
  std::size_t host_queue_frames = 4096;            // the gyro driver's receive queue (2 s at 1 kHz)
  // Each simulated electronics' transmit queue, frames: a CAN controller's mailboxes and its
  // firmware's queue. On an overloaded bus the queue fills and frames are lost at the source
  // (sample overrun, fault bit 4), as on a real bus. 0: unlimited (the node falls behind instead).
  std::size_t node_transmit_queue_frames = 32;
  // The raw-frame tap's queue: 64 Ki frames is 32 s of a 1 kHz classic stream, so a recorder
  // that writes in bursts does not lose frames. Oldest dropped when full (counted).
  std::size_t monitor_queue_frames = 65536;

  // False, with the field and value, when anything is out of range (delegates to the parts).
  bool IsValid(std::string* why) const;
};

// What the simulated gyro follows, for comparing estimates with the truth.
struct SimulatedTruth {
  // physics = carrier: δ and ξ are the physical parameters' mapping (estimator/physical_parameters)
  // and hold to the averaging error; the noise is the converters', sigma is 0.
  bool carrier = false;
  estimator::Delta delta = estimator::Delta::Zero();
  estimator::Xi xi = estimator::Xi::Zero();
  double sigma = 0.0;      // noise std per channel of y (before quantisation to the wire's LSB)
  std::uint64_t seed = 0;  // run r (0-based, per release) uses NormalGenerator(seed + r)
  double earth_rate_rad_s = 0.0;
};

}  // namespace hrgbench::drivers::sim_station
