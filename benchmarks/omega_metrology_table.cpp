// How much a run's Ω matters, and how well the bench knows it: δ3…δ6 over seeds when the estimator
// is given each run's Ω as the bench would measure it on the simulated table, from its rate
// readings (mean) or from its encoder angle (line fit), against the true mean rate. Prints a
// Markdown table (kept in docs/measurements/ with the command that made it).
//
//   omega_metrology_table [--seeds N] [--run-s T]      (defaults: 40 seeds, 100 s runs)
//
// Per seed: the production design (6 runs at ±0.1, ±0.3, ±1 rad/s, θ = kπ/12, b = 0, 0.1, 0.2,
// 1 kHz) simulated exactly (estimator::SimulateRuns, σ = 1e-4, the station's unit: δ = (−0.001,
// 0.3, 0, 0, 0, 0), ξ = (0.01, 0, 0, 0)) with the table's true mean rate over each run; then for
// each run a TablePhysics (drivers/sim, the simulated station's table) commanded to that rate,
// settled, and read as the sequencer reads it: status and angle every 20 ms from the release to
// the end, the angle once more at the end (bench/run_omega.hpp turns the readings into Ω). The
// same gyro data is estimated (EstimateMaximumLikelihood, all ξ, its defaults) with each Ω, so the
// rows differ by the Ω alone; as the bench does, each Ω comes with its standard error
// (RunData::omega_std_rad_s: the estimator takes Ω as a nuisance with that prior), and one row
// gives the rate mean as exact, as the estimator took every Ω before it had the prior. The
// table's rate noise per reading: 1e-6 rad/s (station-sim.toml) and 2e-5 rad/s (TablePhysics'
// default); its encoder: 2^23 counts/rev, 1e-6 rad read noise.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "hrgbench/bench/capture/run_omega.hpp"
#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/simulation.hpp"
#include "sim/table_physics.hpp"

namespace {

using namespace hrgbench;
using estimator::RunData;
using estimator::RunPlan;

constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kReadPeriodNs = 20 * kMs;  // the sequencer's table read period

std::vector<RunPlan> ProductionDesign(double run_s) {
  const double omegas[] = {0.1, -0.1, 0.3, -0.3, 1.0, -1.0};
  std::vector<RunPlan> plans;
  for (int k = 0; k < 6; ++k) {
    RunPlan p;
    p.omega_rad_s = omegas[k];
    p.a = 1.0;
    p.b = 0.1 * (k % 3);
    p.theta_rad = k * std::numbers::pi / 12;
    p.sample_rate_hz = 1000.0;
    p.duration_s = run_s;
    plans.push_back(p);
  }
  return plans;
}

struct TableRun {
  double true_mean_rad_s = 0.0;
  bench::OmegaEstimate by_rate;
  bench::OmegaEstimate by_angle;
};

// One run on the simulated table: command, settle 5 s, then read for run_s as the sequencer does.
TableRun MeasureOnTable(double omega_rad_s, double run_s, double rate_noise_rad_s,
                        std::uint64_t seed) {
  hw::ManualClock clock;
  drivers::sim::TablePhysicsOptions o;
  o.noise_rad_s = rate_noise_rad_s;
  o.seed = seed;
  o.accel_limit_rad_s2 = 1.0;
  drivers::sim::TablePhysics table(o, clock);
  table.Command(hw::RateTableMode::kRate, omega_rad_s);
  std::uint16_t heartbeat = 0;
  for (int i = 0; i < 50; ++i) {
    clock.Advance(100 * kMs);
    table.Heartbeat(++heartbeat);
  }
  bench::RateReadingsMean rate;
  bench::AngleRateFit angle;
  const auto reads = static_cast<std::int64_t>(std::llround(run_s * 1e9 / kReadPeriodNs));
  angle.Reserve(static_cast<std::size_t>(reads) + 2);
  const double phi_start = table.TrueAngleRad();
  angle.Add(table.Angle());  // at the release
  for (std::int64_t i = 0; i < reads; ++i) {
    clock.Advance(kReadPeriodNs);
    table.Heartbeat(++heartbeat);
    rate.Add(table.Status().measured_rate_rad_s);
    angle.Add(table.Angle());
  }
  angle.Add(table.Angle());  // after the capture (same instant here: the loop's last read)
  TableRun r;
  r.true_mean_rad_s = (table.TrueAngleRad() - phi_start) / run_s;
  r.by_rate = rate.Result();
  r.by_angle = angle.Result();
  return r;
}

struct Row {
  Row(std::string row_name, bool std_given)
      : name(std::move(row_name)), omega_std_given(std_given) {}
  std::string name;
  bool omega_std_given = true;              // false: the estimator takes Ω as exact
  std::vector<estimator::Delta> estimates;  // per seed
  double omega_error_sum2 = 0.0;
  double reported_std_sum = 0.0;
  double delta4_reported_std_sum = 0.0;
  int omegas = 0;
  int failed = 0;
};

void Print(const Row& row, const estimator::Delta& truth) {
  const auto n = static_cast<double>(row.estimates.size());
  std::printf("| %s | %s | %.2g | %.2g |", row.name.c_str(), row.omega_std_given ? "yes" : "no",
              std::sqrt(row.omega_error_sum2 / row.omegas), row.reported_std_sum / row.omegas);
  for (int j = 2; j < 6; ++j) {
    double sum = 0.0, sum2 = 0.0;
    for (const auto& d : row.estimates) sum += d[j] - truth[j];
    const double bias = sum / n;
    for (const auto& d : row.estimates) sum2 += (d[j] - truth[j] - bias) * (d[j] - truth[j] - bias);
    std::printf(" %+.2e | %.2e |", bias, std::sqrt(sum2 / (n - 1)));
  }
  std::printf(" %.2e |", row.delta4_reported_std_sum / n);
  if (row.failed > 0) std::printf(" %d estimates failed", row.failed);
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 40;
  double run_s = 100.0;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--seeds") seeds = std::atoi(argv[i + 1]);
    if (flag == "--run-s") run_s = std::atof(argv[i + 1]);
  }
  if (seeds < 2 || !(run_s > 0.0)) {
    std::fprintf(stderr, "usage: omega_metrology_table [--seeds N >= 2] [--run-s T > 0]\n");
    return 2;
  }
  const auto started = std::chrono::steady_clock::now();
  estimator::SimulationOptions truth;
  truth.delta << -0.001, 0.3, 0.0, 0.0, 0.0, 0.0;
  truth.xi << 0.01, 0.0, 0.0, 0.0;
  truth.sigma = 1e-4;

  const double rate_noises[] = {1e-6, 2e-5};
  Row exact("true mean rate", false);
  Row by_angle("angle (line fit; encoder 2^23 counts/rev, 1e-6 rad)", true);
  Row by_rate_low("rate readings' mean, noise 1e-6 rad/s", true);
  Row by_rate_high("rate readings' mean, noise 2e-5 rad/s", true);
  Row by_rate_high_exact("rate readings' mean, noise 2e-5 rad/s", false);
  const estimator::MlOptions options;  // all ξ, all cores
  for (int seed = 1; seed <= seeds; ++seed) {
    std::vector<RunPlan> plans = ProductionDesign(run_s);
    std::vector<TableRun> low, high;
    for (std::size_t k = 0; k < plans.size(); ++k) {
      const std::uint64_t table_seed = static_cast<std::uint64_t>(seed) * 100 + k;
      low.push_back(MeasureOnTable(plans[k].omega_rad_s, run_s, rate_noises[0], table_seed));
      high.push_back(MeasureOnTable(plans[k].omega_rad_s, run_s, rate_noises[1], table_seed));
      plans[k].omega_rad_s = low.back().true_mean_rad_s;  // what the gyro senses
    }
    truth.seed = static_cast<std::uint64_t>(seed);
    std::vector<RunData> runs = estimator::SimulateRuns(plans, truth);
    const auto estimate = [&](Row& row, auto omega_of) {
      for (std::size_t k = 0; k < runs.size(); ++k) {
        const bench::OmegaEstimate e = omega_of(k);
        runs[k].omega_rad_s = e.omega_rad_s;
        runs[k].omega_std_rad_s = row.omega_std_given ? e.std_error_rad_s : 0.0;
        row.omega_error_sum2 +=
            (e.omega_rad_s - plans[k].omega_rad_s) * (e.omega_rad_s - plans[k].omega_rad_s);
        row.reported_std_sum += std::isfinite(e.std_error_rad_s) ? e.std_error_rad_s : 0.0;
        ++row.omegas;
      }
      const estimator::EstimateSummary s = estimator::EstimateMaximumLikelihood(runs, options);
      if (!s.IsUsable()) {
        ++row.failed;
        return;
      }
      row.estimates.push_back(s.delta);
      row.delta4_reported_std_sum += s.delta_std[3];
    };
    estimate(exact, [&](std::size_t k) {
      bench::OmegaEstimate e;
      e.omega_rad_s = plans[k].omega_rad_s;
      e.std_error_rad_s = 0.0;
      return e;
    });
    estimate(by_angle, [&](std::size_t k) { return low[k].by_angle; });
    estimate(by_rate_low, [&](std::size_t k) { return low[k].by_rate; });
    estimate(by_rate_high, [&](std::size_t k) { return high[k].by_rate; });
    estimate(by_rate_high_exact, [&](std::size_t k) { return high[k].by_rate; });
    std::fprintf(stderr, "seed %d of %d\r", seed, seeds);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  std::printf(
      "Production design, %d seeds, %g s runs at 1 kHz, σ = 1e-4; bias and std over seeds of the "
      "estimate minus the truth (δ3…δ6 true 0); Ω error RMS over runs and seeds.\n\n",
      seeds, run_s);
  std::printf(
      "| Ω given to the estimator | its std given | Ω error RMS, rad/s | reported Ω std, rad/s "
      "| δ3 bias | δ3 std | δ4 bias | δ4 std | δ5 bias | δ5 std | δ6 bias | δ6 std "
      "| δ4 std reported |\n"
      "|---|:-:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const Row* row : {&exact, &by_angle, &by_rate_low, &by_rate_high, &by_rate_high_exact})
    Print(*row, truth.delta);
  std::printf("\n(%.0f s on this machine)\n", seconds);
  return 0;
}
