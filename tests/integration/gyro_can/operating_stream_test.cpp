// The simulated electronics run as a gyro behind the CAN protocol (issue 28 §1): Configure with the
// whole-angle run mode, Release, and the OperatingSample stream carries the gyro's angle output,
// computed by the electronics with the parameter block they hold. From that stream alone the rate
// error against the table's rate follows the law of docs/estimator/operating-mode.md (written out
// here), and writing the unit's own parameters over CAN removes it.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "gyro_rig.hpp"
#include "hrgbench/analysis/rate_error_harmonics.hpp"

namespace hrgbench::drivers::gyro_can {
namespace {

using testing::GyroRig;
using testing::GyroRigOptions;
constexpr double kOmega = 0.3;  // the table, rad/s
constexpr double kRateHz = 1000.0;

// Two turns of 2θ as a gyro, read from the stream; the harmonics of Ω̂ − Ω.
analysis::RateErrorHarmonics RunAsGyro(GyroRig& rig, double delta2) {
  EXPECT_TRUE(rig.device->Configure({static_cast<std::uint32_t>(kRateHz), true}).has_value());
  EXPECT_TRUE(rig.device->Excite({1.0, 0.0, 0.3}).has_value());
  EXPECT_TRUE(rig.device->WaitReady(2'000'000'000).has_value());
  const auto released = rig.device->Release();
  EXPECT_TRUE(released.has_value()) << released.error().ToString();
  EXPECT_EQ(rig.device->State(), hw::GyroMode::kOperating);
  const auto n =
      static_cast<std::size_t>(2.0 * 2.0 * std::numbers::pi / (4.0 * delta2 * kOmega) * kRateHz);
  std::vector<OperatingSample> samples(n);
  std::size_t got = 0;
  while (got < n) {
    const std::size_t read =
        rig.device->ReadOperatingSamples(std::span(samples).subspan(got), 1'000'000'000);
    if (read == 0) break;
    got += read;
  }
  EXPECT_EQ(got, n);
  EXPECT_EQ(rig.device->Counters().sequence_gaps, 0u);
  EXPECT_TRUE(rig.device->Stop().has_value());
  // Rates from the angle output's increments; the wave angle unwrapped from its π period.
  std::vector<double> angle, error;
  double theta = samples[0].wave_angle_rad;
  for (std::size_t k = 1; k < got; ++k) {
    EXPECT_EQ(samples[k].index, samples[k - 1].index + 1);
    theta +=
        std::remainder(samples[k].wave_angle_rad - samples[k - 1].wave_angle_rad, std::numbers::pi);
    angle.push_back(theta);
    error.push_back((samples[k].angle_output_rad - samples[k - 1].angle_output_rad) * kRateHz -
                    kOmega);
  }
  auto fit = analysis::FitRateErrorHarmonics(angle, error, 1.0 / kRateHz, 100, 2);
  EXPECT_TRUE(fit.ok) << fit.why;
  return fit;
}

TEST(OperatingStreamTest, TheAngleOutputShowsTheDerivedErrorAndTheUnitsOwnBlockRemovesIt) {
  GyroRigOptions options;
  options.omega_rad_s = kOmega;
  options.sim.delta << -1e-3, 0.3, 3e-5, -2e-5, 0.0, 0.0;
  options.sim.xi << 0.01, 0.0, 0.0, 0.004;
  GyroRig rig(options);
  const double delta2 = 0.3;

  // The factory block: the design's gain and decay, no pick-off inverse, no drift removed.
  const auto before = RunAsGyro(rig, delta2);
  const double c = -(-2e-5) / (2.0 * delta2) - 2.0 * kOmega * 0.01;
  const double s = 3e-5 / (2.0 * delta2) - 2.0 * kOmega * 0.004;
  EXPECT_NEAR(before.cos_rad_s[0], c, 0.02 * std::hypot(c, s));
  EXPECT_NEAR(before.sin_rad_s[0], s, 0.02 * std::hypot(c, s));

  // The unit's own parameters, written over CAN; the same run again.
  const ParameterValues own = {-1e-3, 0.3, 3e-5, -2e-5, 0.0, 0.0, 0.01, 0.0, 0.0, 0.004, 0.0};
  const auto written = rig.device->WriteParameters(own);
  ASSERT_TRUE(written.has_value()) << written.error().ToString();
  const auto after = RunAsGyro(rig, delta2);
  EXPECT_LT(after.angle_dependent_rms_rad_s, before.angle_dependent_rms_rad_s / 1000.0)
      << "before " << before.angle_dependent_rms_rad_s << ", after "
      << after.angle_dependent_rms_rad_s;
  EXPECT_LT(std::abs(after.bias_rad_s), 1e-7);
}

TEST(OperatingStreamTest, TheOperatingModeNeedsSlowPhysicsAndAValidBlock) {
  GyroRigOptions carrier;
  carrier.sim.physics = drivers::sim::GyroPhysics::kCarrier;
  GyroRig rig(carrier);
  const auto refused = rig.device->Configure({1000, true});
  ASSERT_FALSE(refused.has_value());
  EXPECT_EQ(refused.error().code, hw::GyroErrorCode::kRejected);
}

}  // namespace
}  // namespace hrgbench::drivers::gyro_can
