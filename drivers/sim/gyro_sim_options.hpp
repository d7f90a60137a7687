#pragma once
// Options of the simulated HRG electronics (GyroSimNode): which physics makes the samples (the slow
// model's δ, ξ, σ, see docs/estimator/model.md and estimator/simulation.hpp; or the carrier-level
// resonator and electronics, carrier_options.hpp), the electronics' behaviour, and explicit
// failure modes (STYLE rule 6). Plain data with in-class defaults; the program reads it from TOML
// (gyro_sim_config.hpp).

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "gyro_can/gyro_protocol.hpp"
#include "gyro_can/parameter_block.hpp"
#include "hrgbench/estimator/parameters.hpp"
#include "sim/carrier_options.hpp"

namespace hrgbench::drivers::sim {

// Bounds of IsValid that the config file (gyro_sim_config.hpp) checks at their keys as well.
inline constexpr double kMaxAbsXi = 0.25;              // |xi_i| < this: a small perturbation
inline constexpr double kMaxExciteTimeS = 600.0;       // excite_time_s in [0, this]
inline constexpr double kMaxAbsTemperatureC = 327.67;  // the status field's range, 0.01 °C steps

// Failure modes, each off by default. Counts are "the next N"; they decrement as they fire.
struct GyroSimFaults {
  std::uint32_t drop_sample_frames = 0;     // do not send the next N sample frames (seq advances)
  std::uint32_t drop_every_nth_frame = 0;   // additionally drop every Nth sample frame (0 = off)
  std::uint32_t corrupt_sample_frames = 0;  // send the next N sample frames with one bit flipped
                                            // after the CRC was computed
  std::int64_t stall_after_samples = -1;    // the stream stops after N samples (acks continue)
  std::uint64_t stall_from_run = 1;         // ... in the Nth free run since start and later ones
  std::uint32_t ignore_commands = 0;        // no reply (and no action) to the next N commands
  bool no_reply = false;                    // no reply to any command, ever
  std::int64_t bus_off_after_samples = -1;  // after N samples, short the bus (bus-off hook)
  std::uint8_t fault_bits = 0;              // when ≠ 0: latch these gyro_fault bits, mode Faulted
  bool never_ready = false;                 // Excite is acknowledged but the wave never reaches
                                            // its target (mode stays Exciting, ready never set)
  // The compensation parameter block (README "Parameter block"):
  std::uint32_t power_loss_on_commit = 0;    // the next N Commits lose power half-way through
                                             // writing the slot: no Ack, the node restarts (Idle),
                                             // the torn slot fails its CRC, the old block stays
  std::int32_t corrupt_parameter_word = -1;  // staging memory flips bit 0 of this word on Write
};

// Where the free-run samples come from (free_run_source.hpp).
enum class GyroPhysics {
  kSlow,     // the estimator's own model: y = (I + C(ξ))·exp(A·t)·x0 + σ·n (delta, xi, sigma)
  kCarrier,  // the 2-DOF resonator at its carrier and real electronics (carrier)
};

struct GyroSimOptions {
  GyroPhysics physics = GyroPhysics::kSlow;
  // physics = kSlow: the resonator. δ defaults to the paper's experiment (model.md): δ1 = −0.001
  // 1/s, δ2 = 0.3.
  estimator::Delta delta = (estimator::Delta() << -0.001, 0.3, 0.0, 0.0, 0.0, 0.0).finished();
  estimator::Xi xi = estimator::Xi::Zero();
  double sigma = 0.0;  // noise std per channel of y (amplitude units); the paper's 1e-4
  // The operating mode's forcers (either physics; at carrier level in the electrode frame): their
  // complex gain F = I + B(ε) and the command's feed-through D into the pick-off
  // (sim/operating_plant.hpp). Free runs never see them.
  Eigen::Matrix2cd forcer_gain = Eigen::Matrix2cd::Identity();
  Eigen::Matrix2cd feed_through = Eigen::Matrix2cd::Zero();
  std::uint64_t seed = 1;  // run r (0-based, per release) uses NormalGenerator(seed + r)
  // physics = kCarrier: the mode, the pick-off path and the electronics (seeded with seed + r as
  // well). Its frequency is what Status reports (resonant_frequency_hz is the slow physics').
  CarrierOptions carrier;

  // The electronics.
  gyro_can::NodeId node = 0;              // its node id on the bus (0 … gyro_can::kMaxNodeId)
  double excite_time_s = 0.2;             // from Excite to "ready" (control loops settling)
  double resonant_frequency_hz = 5000.0;  // reported by the PLL
  double temperature_c = 25.0;            // reported housing temperature at power-on
  // Linear drift of the housing temperature from power-on (°C/s), e.g. warm-up; 0 = constant.
  double temperature_drift_c_per_s = 0.0;
  bool supports_fd = true;                // accept FrameFormat::kFd (when the bus is FD too)
  std::int64_t poll_period_ns = 200'000;  // firmware loop: commands are answered within this

  // The compensation parameter block the electronics leave the factory with (the paper's p before
  // tuning: the design's decay and angular gain, nothing else; parameter_block.hpp's order).
  gyro_can::ParameterValues factory_parameters = {-1e-3, 0.3, 0.0, 0.0, 0.0, 0.0,
                                                  0.0,   0.0, 0.0, 0.0, 0.0};

  GyroSimFaults faults;

  bool IsValid(std::string* why) const;
};

}  // namespace hrgbench::drivers::sim
