#pragma once
// OperatingPlant: the resonator with the control in it, as the simulated electronics' whole-angle
// loops see it (GyroSimNode's operating mode): one output sample in, one held command out, per
// sample period. Two physics, one contract:
//   - slow: ControlledResonator, the paper's full model in the slow variables (exact ZOH);
//   - carrier: CarrierSimulation driven through its forcers at the carrier, the command modulated
//     onto the electronics' own reference (carrier_simulation.hpp "The operating mode").
// The contract (ControlledResonator's): Observe gives sample k with the command applied until then
// (its feed-through) and the table's Ω for the period that follows; Advance carries the plant over
// that period with the new command held.
//
// Threads: one thread. Real-time: Observe and Advance are allocation-free.

#include <Eigen/Core>
#include <cstdint>
#include <memory>

#include "hrgbench/estimator/model.hpp"
#include "sim/gyro_sim_options.hpp"

namespace hrgbench::drivers::sim {

class OperatingPlant {
 public:
  virtual ~OperatingPlant() = default;
  // Sample k, in the model's I/Q convention (the electronics' loops compute in their own).
  virtual estimator::Observation Observe(double omega_rad_s, const Eigen::Vector4d& u_held) = 0;
  virtual void Advance(const Eigen::Vector4d& u) noexcept = 0;
  // How late the samples show the wave (the demodulator's group delay; 0 in the slow model): the
  // electronics know their own filter, and their readout removes its drag
  // (whole_angle_control.hpp).
  virtual double measurement_delay_s() const noexcept = 0;
};

// Where a release starts the plant.
struct OperatingStart {
  estimator::Orbit orbit;                 // the wave the excitation left
  double omega_rad_s = 0.0;               // Ω at release
  double sample_period_s = 1e-3;          // the loops' step (the protocol's sample period)
  std::uint64_t seed = 1;                 // the noise of this run
  double temperature_c = 25.0;            // at release (carrier physics: f(T))
  double temperature_rate_c_per_s = 0.0;  // its ramp
};

// The plant of `options.physics` for one release (options valid).
std::unique_ptr<OperatingPlant> MakeOperatingPlant(const GyroSimOptions& options,
                                                   const OperatingStart& start);

}  // namespace hrgbench::drivers::sim
