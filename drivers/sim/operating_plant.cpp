#include "sim/operating_plant.hpp"

#include "sim/carrier_simulation.hpp"
#include "sim/controlled_resonator.hpp"

namespace hrgbench::drivers::sim {
namespace {

class SlowPlant final : public OperatingPlant {
 public:
  SlowPlant(const ControlledResonatorTruth& truth, const OperatingStart& start)
      : plant_(truth, start.omega_rad_s, start.sample_period_s,
               estimator::OrbitToState(start.orbit)) {}

  estimator::Observation Observe(double omega_rad_s, const Eigen::Vector4d& u_held) override {
    plant_.SetOmega(omega_rad_s);
    return plant_.Observe(u_held);
  }
  void Advance(const Eigen::Vector4d& u) noexcept override { plant_.Advance(u); }
  double measurement_delay_s() const noexcept override { return 0.0; }

 private:
  ControlledResonator plant_;
};

class CarrierPlant final : public OperatingPlant {
 public:
  CarrierPlant(const GyroSimOptions& options, const OperatingStart& start)
      : simulation_(options.carrier),
        plus_sine_(options.carrier.electronics.iq_convention ==
                   estimator::IqConvention::kPlusSine) {
    simulation_.Release({start.orbit, start.omega_rad_s, 1.0 / start.sample_period_s, start.seed,
                         start.temperature_c, start.temperature_rate_c_per_s});
    simulation_.SetControl(options.forcer_gain, options.feed_through);
  }

  estimator::Observation Observe(double omega_rad_s, const Eigen::Vector4d& u_held) override {
    estimator::Observation y = simulation_.Observe(omega_rad_s, u_held);
    if (plus_sine_) {  // the electronics' loops undo their own output convention
      y[1] = -y[1];
      y[3] = -y[3];
    }
    return y;
  }
  void Advance(const Eigen::Vector4d& u) noexcept override { simulation_.Advance(u); }
  double measurement_delay_s() const noexcept override { return simulation_.group_delay_s(); }

 private:
  CarrierSimulation simulation_;
  bool plus_sine_;
};

}  // namespace

std::unique_ptr<OperatingPlant> MakeOperatingPlant(const GyroSimOptions& options,
                                                   const OperatingStart& start) {
  if (options.physics == GyroPhysics::kCarrier) {
    return std::make_unique<CarrierPlant>(options, start);
  }
  ControlledResonatorTruth truth;
  truth.delta = options.delta;
  truth.xi = options.xi;
  truth.forcer_gain = options.forcer_gain;
  truth.feed_through = options.feed_through;
  truth.sigma = options.sigma;
  truth.seed = start.seed;
  return std::make_unique<SlowPlant>(truth, start);
}

}  // namespace hrgbench::drivers::sim
