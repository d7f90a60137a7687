// A run's Ω from the table (bench/run_omega.hpp): the rate readings' mean and the angle's line fit.
// Synthetic readings whose truth is known exactly (quantisation and time jitter made here, not by
// the code under test), a Monte Carlo check that the reported standard error is the scatter, and
// the simulated table (TablePhysics, rate noise and encoder) read as the sequencer reads it.
#include "hrgbench/bench/capture/run_omega.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include "sim/table_physics.hpp"

namespace hrgbench::bench {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr std::int64_t kMs = 1'000'000;

// An encoder reading of the true angle phi_rad (floor, modulo 2^32) stamped at t_ns.
hw::RateTableAngle Reading(std::int64_t t_ns, double phi_rad, std::uint32_t counts_per_rev,
                           std::int64_t window_ns = 0) {
  hw::RateTableAngle a;
  a.t_ns = t_ns;
  a.window_ns = window_ns;
  a.counts_per_rev = counts_per_rev;
  a.valid = true;
  const long double counts = std::floor(static_cast<long double>(phi_rad) * counts_per_rev /
                                        (2.0L * std::numbers::pi_v<long double>));
  a.count = static_cast<std::uint32_t>(static_cast<std::int64_t>(counts));
  return a;
}

TEST(RateReadingsMean, MeanAndStandardErrorOfTheMean) {
  RateReadingsMean mean;
  EXPECT_FALSE(mean.Result().valid());
  mean.Add(1.0);
  EXPECT_EQ(mean.Result().omega_rad_s, 1.0);
  EXPECT_TRUE(std::isnan(mean.Result().std_error_rad_s));  // one reading: no spread
  for (double x : {2.0, 3.0, 4.0}) mean.Add(x);
  const OmegaEstimate e = mean.Result();
  EXPECT_DOUBLE_EQ(e.omega_rad_s, 2.5);
  EXPECT_DOUBLE_EQ(e.std_error_rad_s, std::sqrt(5.0 / 3.0 / 4.0));  // s^2 = 5/3, n = 4
  EXPECT_EQ(e.readings, 4u);
}

TEST(AngleRateFit, ALineOfQuantisedReadingsGivesItsSlope) {
  // 0.3 rad/s for 100 s, read every 20 ms, 2^23 counts/rev, no jitter. Expected standard error,
  // from the model: q / sqrt(12) per reading, S_tt = N T^2 / q^2 (N uniform points over T, to
  // 1/N): q / (T sqrt(N)) = 1.06e-10 rad/s.
  const std::uint32_t cpr = 1u << 23;
  const double q = kTwoPi / cpr, omega = 0.3, phi0 = 0.123456789;
  AngleRateFit fit;
  const int n = 5001;
  for (int i = 0; i < n; ++i) {
    fit.Add(Reading(1'000'000'000 + i * 20 * kMs, phi0 + omega * i * 0.02, cpr));
  }
  const OmegaEstimate e = fit.Result();
  ASSERT_TRUE(e.valid()) << fit.problem();
  EXPECT_EQ(e.readings, static_cast<std::uint64_t>(n));
  const double expected_se = q / (100.0 * std::sqrt(static_cast<double>(n)));
  // Quantisation residuals have the model's variance, so the Birge ratio is 1 +- 2 %.
  EXPECT_GT(e.std_error_rad_s, 0.95 * expected_se);
  EXPECT_LT(e.std_error_rad_s, 1.1 * expected_se);
  EXPECT_NEAR(e.omega_rad_s, omega, 4 * e.std_error_rad_s);
}

TEST(AngleRateFit, TheCountsWrapWithoutAStep) {
  // The same motion starting 1000 counts before 2^32 and at 0: identical fits.
  const std::uint32_t cpr = 1u << 23;
  for (double omega : {0.5, -0.5}) {
    AngleRateFit at_zero, across_wrap;
    for (int i = 0; i < 200; ++i) {
      const std::int64_t t = i * 20 * kMs;
      const hw::RateTableAngle a = Reading(t, omega * i * 0.02, cpr);
      hw::RateTableAngle b = a;
      b.count = a.count + (0xFFFFFFFFu - 999u);  // modulo 2^32: 1000 counts before the wrap
      at_zero.Add(a);
      across_wrap.Add(b);
    }
    const OmegaEstimate a = at_zero.Result(), b = across_wrap.Result();
    ASSERT_TRUE(a.valid() && b.valid());
    EXPECT_EQ(b.omega_rad_s, a.omega_rad_s) << omega;
    EXPECT_NEAR(a.omega_rad_s, omega, 1e-8) << omega;
  }
}

// One trial of readings with every error the model names and one it does not (read noise): the
// true sampling instant uniform in the read window, quantisation by floor.
struct TrialSetup {
  std::uint32_t cpr = 1u << 16;  // q = 9.6e-5 rad: quantisation and jitter both matter
  double omega = 1.0;
  int readings = 200;
  std::int64_t period_ns = 20 * kMs;
  std::int64_t max_window_ns = 200'000;  // 0..0.2 ms: Omega w / sqrt(12) up to 5.8e-5 rad
  double read_noise_rad = 0.0;
};

double TrialError(const TrialSetup& s, std::mt19937_64& rng, double* std_error) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double phi0 = kTwoPi * unit(rng);
  AngleRateFit fit;
  for (int i = 0; i < s.readings; ++i) {
    const std::int64_t stamp = i * s.period_ns;
    const auto window = static_cast<std::int64_t>(unit(rng) * static_cast<double>(s.max_window_ns));
    const double sampled_s =
        (static_cast<double>(stamp) + (unit(rng) - 0.5) * static_cast<double>(window)) * 1e-9;
    fit.Add(
        Reading(stamp, phi0 + s.omega * sampled_s + s.read_noise_rad * normal(rng), s.cpr, window));
  }
  const OmegaEstimate e = fit.Result();
  *std_error = e.std_error_rad_s;
  return e.omega_rad_s - s.omega;
}

// Over `trials` seeded trials: the scatter of the error over the mean reported standard error,
// and the mean error in units of its own standard error.
void ExpectCalibrated(const TrialSetup& setup, double low, double high) {
  std::mt19937_64 rng(20261123);
  const int trials = 400;
  double sum = 0.0, sum2 = 0.0, se_sum = 0.0;
  for (int k = 0; k < trials; ++k) {
    double se = 0.0;
    const double error = TrialError(setup, rng, &se);
    sum += error;
    sum2 += error * error;
    se_sum += se;
  }
  const double mean = sum / trials;
  const double scatter = std::sqrt(sum2 / trials - mean * mean);
  const double reported = se_sum / trials;
  EXPECT_GT(reported / scatter, low) << "reported " << reported << ", scatter " << scatter;
  EXPECT_LT(reported / scatter, high) << "reported " << reported << ", scatter " << scatter;
  EXPECT_LT(std::abs(mean), 4 * scatter / std::sqrt(static_cast<double>(trials)));  // unbiased
}

TEST(AngleRateFit, ReportedStandardErrorIsTheScatterWithQuantisationAndJitter) {
  // 400 trials: the scatter is known to 1/sqrt(800) = 3.5 %; the Birge ratio's max(1, .) adds
  // a few % on average (chi^2 / 198 scatters by 10 %). Bounds: 0.85 .. 1.2.
  ExpectCalibrated(TrialSetup{}, 0.85, 1.2);
}

TEST(AngleRateFit, ReadNoiseOutsideTheModelShowsInTheResidualsAndIsCounted) {
  // Read noise 3 q, 9 times the quantisation's variance and not in the weights: the residuals'
  // chi^2 inflates the standard error to the scatter (a Birge ratio of ~3).
  TrialSetup s;
  s.max_window_ns = 0;
  s.read_noise_rad = 3 * kTwoPi / s.cpr;
  ExpectCalibrated(s, 0.85, 1.2);
}

TEST(AngleRateFit, AStillTableIsKnownNoBetterThanItsEndPoints) {
  // Omega = 0: every reading is the same count; the fit says 0 and cannot know better than
  // q / (sqrt(6) T) (two independent uniform errors over the span).
  const std::uint32_t cpr = 1u << 23;
  const double q = kTwoPi / cpr;
  AngleRateFit fit;
  for (int i = 0; i <= 500; ++i) fit.Add(Reading(i * 20 * kMs, 1.0, cpr));
  const OmegaEstimate e = fit.Result();
  ASSERT_TRUE(e.valid());
  EXPECT_EQ(e.omega_rad_s, 0.0);
  EXPECT_NEAR(e.std_error_rad_s, q / (std::sqrt(6.0) * 10.0), 1e-20);
}

TEST(AngleRateFit, InvalidReadingsAreLeftOutAndTooFewGiveNoOmega) {
  const std::uint32_t cpr = 1u << 23;
  AngleRateFit fit;
  auto invalid = Reading(0, 0.0, cpr);
  invalid.valid = false;
  fit.Add(invalid);
  fit.Add(Reading(0, 0.0, cpr));
  EXPECT_FALSE(fit.Result().valid());  // one valid reading
  fit.Add(Reading(0, 0.0, cpr));
  EXPECT_FALSE(fit.Result().valid());  // two, at one instant: no slope
  fit.Add(Reading(kMs * 1000, 0.5, cpr));
  EXPECT_TRUE(fit.Result().valid());
  // Points (0, 0), (0, 0), (1 s, 0.5 rad) lie on one line: slope 0.5, to the quantisation.
  EXPECT_NEAR(fit.Result().omega_rad_s, 0.5, 2 * kTwoPi / cpr);
  EXPECT_EQ(fit.valid_readings(), 3u);
  EXPECT_EQ(fit.invalid_readings(), 1u);
  EXPECT_TRUE(fit.problem().empty());
  fit.Add(Reading(kMs * 2000, 1.0, cpr / 2));
  EXPECT_FALSE(fit.Result().valid());
  EXPECT_NE(fit.problem().find("resolution changed"), std::string::npos) << fit.problem();
}

TEST(AngleRateFit, OnTheSimulatedTableItIsWithinItsErrorAndFarBetterThanTheRateMean) {
  // The simulated table as the station's (rate noise 2e-5 rad/s per reading, the physics'
  // default; encoder 2^23 counts/rev, 1e-6 rad read noise), at 0.3 rad/s, read every 20 ms for
  // 100 s as the sequencer does. The truth is the physics' own mean rate over the span, the
  // change of its true angle. Ten seeds, each within 4.5 of its own standard error (a false
  // alarm rate of 7e-6 per check); and the angle's standard error below 1/100 of the rate mean's
  // (model: 4.9e-10 against 2.8e-7).
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    hw::ManualClock clock;
    drivers::sim::TablePhysicsOptions o;
    o.seed = seed;
    o.watchdog_ms = 60000;
    drivers::sim::TablePhysics table(o, clock);
    ASSERT_TRUE(table.Command(hw::RateTableMode::kRate, 0.3));
    clock.Advance(2000 * kMs);  // ramp 0.3 s, then 34 time constants
    RateReadingsMean rate;
    AngleRateFit angle;
    angle.Reserve(5001);
    const double phi_start = table.TrueAngleRad();
    for (int i = 0; i <= 5000; ++i) {
      if (i > 0) clock.Advance(20 * kMs);
      table.Heartbeat(static_cast<std::uint16_t>(i));
      rate.Add(table.Status().measured_rate_rad_s);
      angle.Add(table.Angle());
    }
    const double truth = (table.TrueAngleRad() - phi_start) / 100.0;
    const OmegaEstimate a = angle.Result(), r = rate.Result();
    ASSERT_TRUE(a.valid() && r.valid());
    EXPECT_NEAR(a.omega_rad_s, truth, 4.5 * a.std_error_rad_s) << "seed " << seed;
    EXPECT_NEAR(r.omega_rad_s, truth, 4.5 * r.std_error_rad_s) << "seed " << seed;
    EXPECT_LT(a.std_error_rad_s, r.std_error_rad_s / 100) << "seed " << seed;
    EXPECT_EQ(a.readings, 5001u);
  }
}

}  // namespace
}  // namespace hrgbench::bench
