// What the carrier-level chain does to the current ML estimator: a Markdown table, one row per
// variation of the chain, of each parameter's error in units of the std the estimator reports on
// the production design at σ_y ≈ 1e-4.
//
// Design: the production sequence's 6 runs (Ω = ±0.1, ±0.3, ±1 rad/s, θ = kπ/12, b cycling 0,
// 0.1, 0.2, a = 1), shortened to `--run-s` (default 20 s) at 1 kHz. Data: CarrierSimulation
// (drivers/sim) directly, no CAN; quantised to the wire's LSB. Truth: the unit's physical
// parameters mapped to (δ, ξ) (estimator/physical_parameters.hpp).
//
// Method: every row is simulated NOISE-FREE, so its error is the systematic error alone; the std
// it is divided by is the Cramér–Rao bound of the row's design (truth, runs) at the σ_y that
// EstimateMaximumLikelihood finds on the baseline chain with white converter noise (σ_y ≈ 1e-4):
// the std the estimator would report (its covariance is the CRLB at the estimate; the first two
// rows show the reported std and the bound agree). The "noisy baseline" row's own errors are noise.
// |error/std| ≫ 1 is a bias the slow model cannot absorb; residual RMS is the model error left.
//
// Usage: build/bin/carrier_accuracy_table [--run-s 20] [--only TEXT]   (prints to stdout; minutes
// on 2 cores; --only: the rows whose name contains TEXT)
//        build/bin/carrier_accuracy_table --seeds N [--chain baseline|tracking] [--run-s 20]
//            [--declare none|chain|ORDER:CUTOFF_HZ] [--coloured-noise STD --coloured-time S]
// (the Monte Carlo of RunMonteCarlo below: N noisy sessions, the reported std against the scatter,
// the fit told the noise shape --declare names: none = white, chain = the chain's output filter)

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "hrgbench/estimator/cramer_rao.hpp"
#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/noise_shape.hpp"
#include "hrgbench/estimator/physical_parameters.hpp"
#include "hrgbench/estimator/reference_phase.hpp"
#include "sim/carrier_simulation.hpp"

namespace {

using hrgbench::drivers::sim::CarrierOptions;
using hrgbench::drivers::sim::CarrierRelease;
using hrgbench::drivers::sim::CarrierSimulation;
using hrgbench::drivers::sim::ReferenceMode;
namespace est = hrgbench::estimator;

constexpr double kPi = std::numbers::pi;
constexpr double kWhiteNoise = 1.1e-3;  // → σ_y ≈ 1.0e-4 through the 200 Hz 4th-order filter

// The unit of bench_configs/station-sim-carrier.toml, noise-free, common delay 0.
CarrierOptions Baseline() {
  CarrierOptions o;
  o.resonator.frequency_hz = 5000.0;
  o.resonator.decay_time_s = 1000.0;
  o.resonator.damping_anisotropy_per_s = 2e-5;
  o.resonator.damping_axis_rad = -0.4;
  o.resonator.frequency_split_hz = 2e-4;
  o.resonator.frequency_axis_rad = 0.2;
  o.resonator.angular_gain = 0.3;
  o.pickoff.errors = {0.98, 0.002, 0.001, 0.002};
  o.sample_rate_hz = 100000.0;
  o.electronics.filter_order = 4;
  o.electronics.filter_cutoff_hz = 200.0;
  return o;
}

struct Design {
  double run_s = 20.0;
  double output_rate_hz = 1000.0;
  double omega_scale = 1.0;
  double discard_s = 0.0;  // samples dropped at the start of each run
  double temperature_rate_c_per_s = 0.0;
  // Per run, set the free-running reference to the mean of the two modes' exact frequencies under
  // that run's Ω (eigenvalues of the oscillator), i.e. remove the common drift
  // ν ≈ (2kΩ)²/(2ω0) that the slow model has no term for (a diagnostic).
  bool lock_to_mean_mode_frequency = false;
  // Turn each sample back by the reference phase the electronics report with it
  // (CarrierElectronics::reported_phase_rad, estimator/reference_phase.hpp): what a bench does
  // with electronics that report their tracking reference.
  bool undo_reference_phase = false;
};

// ν: mean of the two modes' exact angular frequencies minus 2π·f0, rad/s.
double CommonDrift(const CarrierOptions& options, double omega) {
  hrgbench::drivers::sim::CarrierResonator resonator(options.resonator, 1e-5);
  resonator.SetConditions(omega, 1.0);
  const Eigen::Vector4cd eigen = resonator.system_matrix().eigenvalues();
  double sum = 0.0;
  for (int i = 0; i < 4; ++i) sum += std::abs(eigen[i].imag());
  return 0.25 * sum - resonator.mean_frequency_rad_s();
}

const double kOmegas[6] = {0.1, -0.1, 0.3, -0.3, 1.0, -1.0};
const double kBs[6] = {0.0, 0.1, 0.2, 0.0, 0.1, 0.2};

// The CRLB of the design at σ: the std the estimator reports for it.
est::CrlbResult Bound(const est::Delta& delta, const est::Xi& xi, const Design& design,
                      double sigma) {
  est::DesignSpec spec;
  spec.delta = delta;
  spec.xi = xi;
  spec.sigma = sigma;
  for (int r = 0; r < 6; ++r) {
    est::RunPlan plan;
    plan.omega_rad_s = kOmegas[r] * design.omega_scale;
    plan.a = 1.0;
    plan.b = kBs[r];
    plan.theta_rad = r * kPi / 12.0;
    plan.sample_rate_hz = design.output_rate_hz;
    plan.duration_s = design.run_s;
    spec.runs.push_back(plan);
  }
  return est::CramerRaoBound(spec);
}

std::vector<est::RunData> Simulate(const CarrierOptions& options, const Design& design,
                                   std::uint64_t seed) {
  std::optional<CarrierSimulation> sim(options);
  std::vector<est::RunData> runs;
  for (int r = 0; r < 6; ++r) {
    const double omega = kOmegas[r] * design.omega_scale;
    if (design.lock_to_mean_mode_frequency) {
      CarrierOptions locked = options;
      locked.electronics.reference.offset_hz = CommonDrift(options, omega) / (2 * kPi);
      sim.emplace(locked);
    }
    CarrierRelease release;
    release.orbit = {1.0, kBs[r], r * kPi / 12.0, 0.0};
    release.omega_rad_s = omega;
    release.output_rate_hz = design.output_rate_hz;
    release.seed = seed + static_cast<std::uint64_t>(r);
    release.temperature_c = 25.0;
    release.temperature_rate_c_per_s = design.temperature_rate_c_per_s;
    sim->Release(release);
    const long n = std::lround(design.run_s * design.output_rate_hz);
    const long skip = std::lround(design.discard_s * design.output_rate_hz);
    est::RunData run;
    run.id = r + 1;
    run.omega_rad_s = omega;
    run.y.resize(4, n - skip);
    std::vector<double> chi;
    for (long k = 0; k < n; ++k) {
      const est::Observation y = sim->Next(omega);
      if (k < skip) continue;
      run.t_s.push_back(static_cast<double>(k) / design.output_rate_hz);
      run.y.col(k - skip) = y;
      chi.push_back(sim->electronics().reported_phase_rad());
    }
    if (design.undo_reference_phase) est::UndoReferencePhase(run.y, chi);
    runs.push_back(std::move(run));
  }
  return runs;
}

struct Row {
  std::string name;
  std::function<void(CarrierOptions&, Design&)> change;
};

void PrintRow(const std::string& name, const est::EstimateSummary& s, const est::Delta& delta,
              const est::Xi& xi, const est::Delta& delta_std, const est::Xi& xi_std) {
  std::printf("| %s |", name.c_str());
  if (!s.IsUsable()) {
    std::printf(" estimate failed: %s |\n", s.message.c_str());
    return;
  }
  double worst = 0.0;
  for (int j = 0; j < 6; ++j) {
    const double z = (s.delta[j] - delta[j]) / delta_std[j];
    worst = std::max(worst, std::abs(z));
    std::printf(" %+.1f |", z);
  }
  for (int k = 0; k < 4; ++k) {
    const double z = (s.xi[k] - xi[k]) / xi_std[k];
    worst = std::max(worst, std::abs(z));
    std::printf(" %+.1f |", z);
  }
  std::printf(" %.1f | %.2e |\n", worst, s.residual_rms);
}

// --seeds N: the Monte Carlo. N independent noisy sessions of the design (converter noise seeded
// 1000·i + run), each fitted as the production fit does; per parameter: the mean error in units of
// the reported std, the scatter (sample std of the estimates over the seeds) over the mean
// reported std, and the share of estimates more than 2 of their own reported std from the truth.
// For a right estimator with an honest std: ≈ 0 ± 1/√N, ≈ 1 ± 1/√(2(N − 1)), ≈ 4.6 %.
int RunMonteCarlo(const CarrierOptions& options, const Design& design, int seeds,
                  const est::MlOptions& ml, const char* chain) {
  CarrierSimulation probe(options);
  const est::Delta delta = probe.delta();
  const est::Xi xi = probe.xi();
  std::vector<Eigen::Matrix<double, 10, 1>> estimates, stds;
  int flagged = 0, failed = 0;
  std::string last_covariance;
  double worst_ratio = 0.0, worst_z = -1e300;
  for (int i = 0; i < seeds; ++i) {
    const est::EstimateSummary s = est::EstimateMaximumLikelihood(
        Simulate(options, design, 1000u * static_cast<std::uint64_t>(i + 1)), ml);
    last_covariance = s.diagnostics.covariance_kind;
    if (!s.IsUsable()) {
      ++failed;
      continue;
    }
    if (!s.diagnostics.Acceptable()) ++flagged;
    for (const est::RunFitDiagnostics& run : s.diagnostics.runs) {
      worst_ratio = std::max(worst_ratio, run.residual_ratio);
      worst_z = std::max(worst_z, run.whiteness_z);
    }
    Eigen::Matrix<double, 10, 1> e, d;
    e << s.delta, s.xi;
    d << s.delta_std, s.xi_std;
    estimates.push_back(e);
    stds.push_back(d);
  }
  const int n = static_cast<int>(estimates.size());
  std::printf(
      "Carrier Monte Carlo: %s; production design, 6 runs × %.0f s at %.0f Hz; noise declared: "
      "%s; %d seeds, %d fits failed, %d flagged by the fit diagnostics (worst residual ratio "
      "%.4f, worst whiteness z %.2f over the runs); covariance: %s.\n\n",
      chain, design.run_s, design.output_rate_hz, ml.noise_shape.description.c_str(), seeds, failed,
      flagged, worst_ratio, worst_z, last_covariance.c_str());
  if (n < 2) return 1;
  Eigen::Matrix<double, 10, 1> truth;
  truth << delta, xi;
  std::printf(
      "| parameter | truth | mean reported std | scatter | mean error / std | scatter / reported "
      "std | beyond 2 std |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|\n");
  const char* names[10] = {"δ1", "δ2", "δ3", "δ4", "δ5", "δ6", "ξ1", "ξ2", "ξ3", "ξ4"};
  for (int j = 0; j < 10; ++j) {
    double mean = 0.0, mean_std = 0.0;
    int beyond = 0;
    for (int i = 0; i < n; ++i) {
      mean += estimates[i][j] / n;
      mean_std += stds[i][j] / n;
      if (std::abs(estimates[i][j] - truth[j]) > 2.0 * stds[i][j]) ++beyond;
    }
    double scatter = 0.0;
    for (int i = 0; i < n; ++i) scatter += (estimates[i][j] - mean) * (estimates[i][j] - mean);
    scatter = std::sqrt(scatter / (n - 1));
    std::printf("| %s | %+.4e | %.2e | %.2e | %+.2f | %.2f | %.1f %% |\n", names[j], truth[j],
                mean_std, scatter, (mean - truth[j]) / mean_std, scatter / mean_std,
                100.0 * beyond / n);
  }
  std::printf(
      "\nStatistical resolution at N = %d: mean error ± %.2f, scatter/std ± %.2f (1 std of the "
      "estimate of each).\n",
      n, 1.0 / std::sqrt(n), 1.0 / std::sqrt(2.0 * (n - 1)));
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  Design base_design;
  std::string only;                // --only TEXT: the rows whose name contains TEXT
  int seeds = 0;                   // --seeds N: the Monte Carlo instead of the table
  std::string chain = "baseline";  // --chain baseline|tracking: the Monte Carlo's chain
  // --declare none|chain|ORDER:CUTOFF_HZ: the noise shape the fit is told (none = white; chain =
  // the chain's own output filter; else a Butterworth of that order and cutoff).
  std::string declare = "none";
  double coloured_noise_std = 0.0;  // --coloured-noise STD: AR(1) converter noise beside the white
  double coloured_noise_time_s = 1e-3;  // --coloured-time S: its correlation time
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--declare") == 0) declare = argv[i + 1];
    if (std::strcmp(argv[i], "--coloured-noise") == 0) coloured_noise_std = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--coloured-time") == 0)
      coloured_noise_time_s = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--run-s") == 0) base_design.run_s = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--only") == 0) only = argv[i + 1];
    if (std::strcmp(argv[i], "--seeds") == 0) seeds = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--chain") == 0) chain = argv[i + 1];
  }
  est::MlOptions ml;
  ml.num_threads = 1;
  if (seeds > 0) {
    CarrierOptions options = Baseline();
    options.pickoff.white_noise_std = kWhiteNoise;
    options.pickoff.coloured_noise_std = coloured_noise_std;
    options.pickoff.coloured_noise_time_s = coloured_noise_time_s;
    Design design = base_design;
    if (declare != "none") {
      int order = options.electronics.filter_order;
      double cutoff_hz = options.electronics.filter_cutoff_hz;
      if (declare != "chain" && std::sscanf(declare.c_str(), "%d:%lf", &order, &cutoff_hz) != 2) {
        std::fprintf(stderr, "--declare must be none, chain or ORDER:CUTOFF_HZ\n");
        return 2;
      }
      const auto shape = est::ButterworthNoiseShape(order, cutoff_hz, design.output_rate_hz);
      if (!shape) {
        std::fprintf(stderr, "--declare %s: not a usable Butterworth\n", declare.c_str());
        return 2;
      }
      ml.noise_shape = *shape;
    }
    std::string name = "baseline chain (free-running reference), white converter noise σ_y ≈ 1e-4";
    if (chain == "tracking") {
      options.electronics.reference.mode = ReferenceMode::kTracking;
      options.electronics.reference.pll_bandwidth_hz = 2.0;
      design.undo_reference_phase = true;
      name = "tracking PLL 2 Hz with its reported phase undone, white converter noise σ_y ≈ 1e-4";
    } else if (chain != "baseline") {
      std::fprintf(stderr, "--chain must be baseline or tracking\n");
      return 2;
    }
    return RunMonteCarlo(options, design, seeds, ml, name.c_str());
  }

  // The std every row is measured in: the baseline chain with converter noise.
  CarrierOptions noisy = Baseline();
  noisy.pickoff.white_noise_std = kWhiteNoise;
  CarrierSimulation probe(noisy);
  const est::Delta delta = probe.delta();
  const est::Xi xi = probe.xi();
  const est::EstimateSummary reference =
      est::EstimateMaximumLikelihood(Simulate(noisy, base_design, 12345), ml);
  if (!reference.IsUsable()) {
    std::fprintf(stderr, "the noisy baseline did not estimate: %s\n", reference.message.c_str());
    return 1;
  }

  std::printf(
      "Production design, 6 runs × %.0f s at 1 kHz; carrier 5 kHz, converters 100 kHz; "
      "unit of station-sim-carrier.toml.\n",
      base_design.run_s);
  std::printf(
      "Error of each parameter in units of the std reported at σ_y = %.2e "
      "(noisy baseline); rows other than the first are noise-free.\n\n",
      reference.noise_sigma);
  std::printf("| chain | δ1 | δ2 | δ3 | δ4 | δ5 | δ6 | ξ1 | ξ2 | ξ3 | ξ4 | max | residual RMS |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  PrintRow("noisy baseline (σ_y ≈ 1e-4; its errors are noise)", reference, delta, xi,
           reference.delta_std, reference.xi_std);
  std::printf("| reported std |");
  for (int j = 0; j < 6; ++j) std::printf(" %.1e |", reference.delta_std[j]);
  for (int k = 0; k < 4; ++k) std::printf(" %.1e |", reference.xi_std[k]);
  std::printf(" | |\n");
  const est::CrlbResult baseline_bound = Bound(delta, xi, base_design, reference.noise_sigma);
  std::printf("| CRLB at that σ_y |");
  for (int j = 0; j < 6; ++j) std::printf(" %.1e |", baseline_bound.delta_std[j]);
  for (int k = 0; k < 4; ++k) std::printf(" %.1e |", baseline_bound.xi_std[k]);
  std::printf(" | |\n");

  const std::vector<Row> rows = {
      {"baseline: free-running ref. at f0, 4th-order 200 Hz, Δf = 0.2 mHz", {}},
      {"... first 20 ms of each run discarded",
       [](CarrierOptions&, Design& d) { d.discard_s = 0.02; }},
      {"... and the reference at the modes' exact mean frequency per run (ν removed)",
       [](CarrierOptions&, Design& d) {
         d.discard_s = 0.02;
         d.lock_to_mean_mode_frequency = true;
       }},
      {"reference offset +0.1 mHz",
       [](CarrierOptions& o, Design&) { o.electronics.reference.offset_hz = 1e-4; }},
      {"reference offset +1 mHz",
       [](CarrierOptions& o, Design&) { o.electronics.reference.offset_hz = 1e-3; }},
      {"reference offset +10 mHz",
       [](CarrierOptions& o, Design&) { o.electronics.reference.offset_hz = 1e-2; }},
      {"tracking PLL, 1 Hz",
       [](CarrierOptions& o, Design&) {
         o.electronics.reference.mode = ReferenceMode::kTracking;
         o.electronics.reference.pll_bandwidth_hz = 1.0;
       }},
      {"tracking PLL, 10 Hz",
       [](CarrierOptions& o, Design&) {
         o.electronics.reference.mode = ReferenceMode::kTracking;
         o.electronics.reference.pll_bandwidth_hz = 10.0;
       }},
      {"tracking PLL, 1 Hz, reported reference phase undone",
       [](CarrierOptions& o, Design& d) {
         o.electronics.reference.mode = ReferenceMode::kTracking;
         o.electronics.reference.pll_bandwidth_hz = 1.0;
         d.undo_reference_phase = true;
       }},
      {"tracking PLL, 10 Hz, reported reference phase undone",
       [](CarrierOptions& o, Design& d) {
         o.electronics.reference.mode = ReferenceMode::kTracking;
         o.electronics.reference.pll_bandwidth_hz = 10.0;
         d.undo_reference_phase = true;
       }},
      {"tracking PLL, 10 Hz, filter 50 Hz (delay 8.3 ms), phase undone",
       [](CarrierOptions& o, Design& d) {
         o.electronics.reference.mode = ReferenceMode::kTracking;
         o.electronics.reference.pll_bandwidth_hz = 10.0;
         o.electronics.filter_cutoff_hz = 50.0;
         d.undo_reference_phase = true;
       }},
      {"filter 50 Hz (delay 8.3 ms)",
       [](CarrierOptions& o, Design&) { o.electronics.filter_cutoff_hz = 50.0; }},
      {"filter 500 Hz (delay 0.83 ms)",
       [](CarrierOptions& o, Design&) { o.electronics.filter_cutoff_hz = 500.0; }},
      {"filter 8th order, 200 Hz",
       [](CarrierOptions& o, Design&) { o.electronics.filter_order = 8; }},
      {"common pick-off delay 20 µs",
       [](CarrierOptions& o, Design&) { o.pickoff.common_delay_s = 20e-6; }},
      {"no frequency split",
       [](CarrierOptions& o, Design&) { o.resonator.frequency_split_hz = 0.0; }},
      {"frequency split 0.01 Hz",
       [](CarrierOptions& o, Design&) { o.resonator.frequency_split_hz = 0.01; }},
      {"frequency split 0.1 Hz",
       [](CarrierOptions& o, Design&) { o.resonator.frequency_split_hz = 0.1; }},
      {"frequency split 1 Hz",
       [](CarrierOptions& o, Design&) { o.resonator.frequency_split_hz = 1.0; }},
      {"Ω × 0.1 (±0.01, ±0.03, ±0.1 rad/s)",
       [](CarrierOptions&, Design& d) { d.omega_scale = 0.1; }},
      {"Ω × 3 (±0.3, ±0.9, ±3 rad/s)", [](CarrierOptions&, Design& d) { d.omega_scale = 3.0; }},
      {"Ω × 3, ν removed, first 20 ms discarded",
       [](CarrierOptions&, Design& d) {
         d.omega_scale = 3.0;
         d.discard_s = 0.02;
         d.lock_to_mean_mode_frequency = true;
       }},
      {"frequency split 1 Hz, ν removed, first 20 ms discarded",
       [](CarrierOptions& o, Design& d) {
         o.resonator.frequency_split_hz = 1.0;
         d.discard_s = 0.02;
         d.lock_to_mean_mode_frequency = true;
       }},
      {"... the same with an ideal pick-off (ξ = 0)",
       [](CarrierOptions& o, Design& d) {
         o.resonator.frequency_split_hz = 1.0;
         o.pickoff.errors = {};
         d.discard_s = 0.02;
         d.lock_to_mean_mode_frequency = true;
       }},
      {"converters at 20 kHz (4 × f0)",
       [](CarrierOptions& o, Design&) { o.sample_rate_hz = 20000.0; }},
      {"converters at 500 kHz", [](CarrierOptions& o, Design&) { o.sample_rate_hz = 500000.0; }},
      {"output at 250 Hz (filter 50 Hz)",
       [](CarrierOptions& o, Design& d) {
         d.output_rate_hz = 250.0;
         o.electronics.filter_cutoff_hz = 50.0;
       }},
      {"temperature ramp 0.01 °C/s, α = 5e-5/°C (f drifts 2.5 mHz/s)",
       [](CarrierOptions& o, Design& d) {
         o.frequency_temperature_coefficient_per_c = 5e-5;
         d.temperature_rate_c_per_s = 0.01;
       }},
  };
  for (const Row& row : rows) {
    if (!only.empty() && row.name.find(only) == std::string::npos) continue;
    CarrierOptions options = Baseline();
    Design design = base_design;
    if (row.change) row.change(options, design);
    std::string why;
    if (!options.IsValid(&why)) {
      std::printf("| %s | invalid: %s |\n", row.name.c_str(), why.c_str());
      continue;
    }
    CarrierSimulation truth(options);
    CarrierRelease ramp;  // the truth of a release with the row's temperature ramp (δ1 moves)
    ramp.temperature_rate_c_per_s = design.temperature_rate_c_per_s;
    truth.Release(ramp);
    const est::EstimateSummary s = est::EstimateMaximumLikelihood(Simulate(options, design, 1), ml);
    const est::CrlbResult bound = Bound(truth.delta(), truth.xi(), design, reference.noise_sigma);
    PrintRow(row.name, s, truth.delta(), truth.xi(), bound.delta_std, bound.xi_std);
    std::fflush(stdout);
  }
  return 0;
}
