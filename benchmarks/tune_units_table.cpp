// Issue 28's criterion measured at the bench, the way `hrg-bench run --tune` runs it: N simulated
// units drawn around the line's spread (slow model), each through the production session on the
// in-process simulated station (bench::RunSession), then tuned (bench::TuneUnit: p written over
// CAN, refined, verified at ±0.3 rad/s). Per unit: the session's outcome, the angle-dependent rate
// error before and after at each rate and the factor between them, the after holds' χ² against
// the refined p's prediction; over all units, the χ² summed on its degrees of freedom (measured
// and predicted residuals agree when it is within the χ² distribution's spread) and the smallest
// improvement.
//
//   tune_units_table [--units N] [--seed S] [--physics slow|carrier]
//
// The truth, per unit i (std::mt19937_64 seeded S + i): δ1 ∈ [−1.4e-3, −0.7e-3] 1/s, δ2 ∈
// [0.29, 0.31], δ3, δ4 ∈ ±3e-5 1/s, δ5, δ6 ∈ ±3e-4 rad/s, ξ1 ∈ ±0.015, ξ2 … ξ4 ∈ ±5e-3, pick-off
// noise 1e-4, the forcers' β1 … β4 ∈ ±3e-3 and frame b ∈ ±2e-3 (which free runs cannot see), the
// simulator's seed S + i. With --physics carrier (station-sim-carrier.toml: the resonator at its
// 5 kHz carrier, the pick-off channels and the demodulating electronics, the forcers driven at the
// carrier) the unit is drawn in physical units instead: τ ∈ [700, 1400] s, k ∈ [0.29, 0.31],
// Δ(1/τ) ∈ [0, 6e-5] 1/s and Δf ∈ [0, 2e-4] Hz at axes ∈ ±π/2, gain ratio ∈ [0.97, 1.03], phase
// mismatch, electrode angle ∈ ±3e-3 rad, cross-talk ∈ ±2e-3, the same forcer errors (in the
// electrode frame). "With p" is the refine hold at +0.3 rad/s: what p from the free runs leaves,
// the forcers' drift.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "app/station_factory.hpp"
#include "hrgbench/analysis/allan_deviation.hpp"
#include "hrgbench/bench/sequencer/operator_prompts.hpp"
#include "hrgbench/bench/sequencer/sequencer.hpp"
#include "hrgbench/bench/tuning/tune_unit.hpp"
#include "hrgbench/config/bench_configs.hpp"
#include "hrgbench/config/site.hpp"
#include "hrgbench/estimator/compensation.hpp"

namespace {

using namespace hrgbench;

class ConfirmEveryPrompt final : public bench::PromptAnswers {
 public:
  void Show(const bench::PromptRequest&) override {}
  std::optional<bench::PromptReply> Wait(std::chrono::milliseconds) override {
    return bench::PromptReply{true, "tune_units_table", "auto"};
  }
};

constexpr double kDegPerHour = 180.0 / 3.14159265358979323846 * 3600.0;

}  // namespace

int main(int argc, char** argv) {
  int units = 20;
  std::uint64_t seed = 2800;
  bool carrier = false;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--units") units = std::clamp(std::atoi(argv[i + 1]), 1, 1000);
    if (flag == "--seed") seed = std::strtoull(argv[i + 1], nullptr, 10);
    if (flag == "--physics") carrier = std::string(argv[i + 1]) == "carrier";
  }
  const std::filesystem::path configs_dir =
      std::filesystem::path(HRGBENCH_SOURCE_DIR) / "bench_configs";
  const std::filesystem::path work =
      std::filesystem::temp_directory_path() / ("tune_units_table-" + std::to_string(::getpid()));
  std::printf(
      "| unit | session | before +0.3 (°/h) | with p +0.3 | after +0.3 | before −0.3 | after −0.3 "
      "| "
      "smallest factor | χ² (6 dof) | tuned |\n|---|---|---|---|---|---|---|---|---|---|\n");
  double chi2_sum = 0.0;
  int dof = 0, tuned_units = 0;
  double smallest = INFINITY;
  for (int i = 0; i < units; ++i) {
    std::mt19937_64 rng(seed + static_cast<std::uint64_t>(i));
    const auto uniform = [&rng](double a, double b) {
      return std::uniform_real_distribution<double>(a, b)(rng);
    };
    auto configs = bench::LoadBenchConfigs(
        configs_dir / (carrier ? "station-sim-carrier.toml" : "station-sim.toml"),
        configs_dir / "sequence-production.toml", configs_dir / "limits-example.toml");
    if (!configs) {
      std::fprintf(stderr, "%s\n", configs.error().ToString().c_str());
      return 2;
    }
    configs->station.results_url.clear();
    bench::SimulatedStationConfig& sim = configs->station.simulated;
    if (carrier) {
      estimator::ResonatorParameters& r = sim.carrier.resonator;
      r.decay_time_s = uniform(700.0, 1400.0);
      r.angular_gain = uniform(0.29, 0.31);
      r.damping_anisotropy_per_s = uniform(0.0, 6e-5);
      r.damping_axis_rad = uniform(-1.57, 1.57);
      r.frequency_split_hz = uniform(0.0, 2e-4);
      r.frequency_axis_rad = uniform(-1.57, 1.57);
      estimator::PickoffParameters& e = sim.carrier.pickoff;
      e.gain_ratio = uniform(0.97, 1.03);
      e.phase_mismatch_rad = uniform(-3e-3, 3e-3);
      e.cross_talk = uniform(-2e-3, 2e-3);
      e.electrode_angle_error_rad = uniform(-3e-3, 3e-3);
    } else {
      sim.delta << uniform(-1.4e-3, -0.7e-3), uniform(0.29, 0.31), uniform(-3e-5, 3e-5),
          uniform(-3e-5, 3e-5), uniform(-3e-4, 3e-4), uniform(-3e-4, 3e-4);
      sim.xi << uniform(-0.015, 0.015), uniform(-5e-3, 5e-3), uniform(-5e-3, 5e-3),
          uniform(-5e-3, 5e-3);
    }
    sim.forcer_errors = {uniform(-3e-3, 3e-3), uniform(-3e-3, 3e-3), uniform(-3e-3, 3e-3),
                         uniform(-3e-3, 3e-3), uniform(-2e-3, 2e-3)};
    sim.seed = seed + static_cast<std::uint64_t>(i);
    auto station = app::OpenStation(configs->station);
    if (!station) {
      std::fprintf(stderr, "%s\n", station.error().c_str());
      return 2;
    }
    ConfirmEveryPrompt confirm;
    bench::RunnerOptions options;
    options.unit_serial = "TUNE-" + std::to_string(i);
    options.software_version = "tune_units_table";
    options.simulation = (*station)->simulation();
    options.prompts = &confirm;
    const std::filesystem::path dir = work / std::to_string(i);
    const bench::SessionResult session =
        bench::RunSession(*configs, (*station)->hardware(), dir, options);
    estimator::CompensationSet p;
    if (!session.estimate || !estimator::CompensationFromEstimate(*session.estimate, &p)) {
      std::printf("| %d | %s | – | – | – | – | – | – | – | no estimate |\n", i,
                  std::string(bench::ToString(session.outcome)).c_str());
      continue;
    }
    const bench::BenchHardware& hardware = (*station)->hardware();
    const bench::TuneResult tuned =
        bench::TuneUnit(hardware, hardware.units.front(), p, bench::TunePlan{},
                        bench::EarthRateOnAxisRadS(configs->station.site));
    if (tuned.verified.size() != 2) {
      std::printf("| %d | %s | – | – | – | – | – | – | – | %s |\n", i,
                  std::string(bench::ToString(session.outcome)).c_str(), tuned.why.c_str());
      continue;
    }
    double factor = INFINITY;
    for (const bench::VerifiedRate& v : tuned.verified)
      factor = std::min(factor, v.before_rms_rad_s / v.after_rms_rad_s);
    smallest = std::min(smallest, factor);
    chi2_sum += tuned.chi2;
    dof += tuned.chi2_dof;
    tuned_units += tuned.ok ? 1 : 0;
    std::printf("| %d | %s | %.4g | %.3g | %.3g | %.4g | %.3g | %.0f | %.2f | %s |\n", i,
                std::string(bench::ToString(session.outcome)).c_str(),
                tuned.verified[0].before_rms_rad_s * kDegPerHour,
                tuned.refine[0].fit.angle_dependent_rms_rad_s * kDegPerHour,
                tuned.verified[0].after_rms_rad_s * kDegPerHour,
                tuned.verified[1].before_rms_rad_s * kDegPerHour,
                tuned.verified[1].after_rms_rad_s * kDegPerHour, factor, tuned.chi2,
                tuned.ok ? "yes" : tuned.why.c_str());
    std::filesystem::remove_all(dir);
  }
  std::filesystem::remove_all(work);
  std::printf(
      "\n%d of %d units tuned; smallest improvement %.0f×; χ² summed over the after holds %.1f on "
      "%d degrees of freedom (the central 99.8 %% of χ²(%d): [%.1f, %.1f])\n",
      tuned_units, units, smallest, chi2_sum, dof, dof,
      dof > 0 ? analysis::ChiSquaredQuantile(0.001, dof) : 0.0,
      dof > 0 ? analysis::ChiSquaredQuantile(0.999, dof) : 0.0);
  return 0;
}
