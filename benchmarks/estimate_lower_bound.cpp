// How far the whole estimate of a production session is from a practical lower bound (issue 8,
// section 5). Prints a Markdown table.
//
//   estimate_lower_bound [--runs-s S]
//
// The bound: reading and parsing the session (session::ReadSession), plus five passes of the
// sample loop's irreducible work — the five basis functions e^{αt}·(f0, f1, t·f0, t·f1, ∂f1/∂μ²)
// advanced by one complex product per sample, their 15 Gram products and 10 projected residuals —
// written here from scratch, single-threaded, on the same data. Five passes is what
// Levenberg–Marquardt needs from a good start (three linearisations, a cost, the residuals). The
// measured process is ReadSession + EstimateMaximumLikelihood with its defaults on one thread and
// on all. Each figure is the median of 5 repetitions.

#include <algorithm>
#include <chrono>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/simulation.hpp"
#include "hrgbench/session/session.hpp"

namespace {

using Complex = std::complex<double>;
namespace fs = std::filesystem;

template <typename Fn>
double MedianMs(Fn fn, int repeats = 5) {
  std::vector<double> ms;
  for (int i = 0; i < repeats; ++i) {
    const auto start = std::chrono::steady_clock::now();
    fn();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                     .count());
  }
  std::sort(ms.begin(), ms.end());
  return ms[ms.size() / 2];
}

// The irreducible sample loop: 5 basis functions by recurrence, 15 Gram sums, 10 projections.
double GramPass(const std::vector<hrgbench::estimator::RunData>& runs) {
  double checksum = 0.0;
  const Complex mu(1e-3, 0.6);  // a typical μ at Ω = 1 rad/s
  for (const auto& run : runs) {
    const double dt = run.t_s.size() > 1 ? run.t_s[1] - run.t_s[0] : 1e-3;
    const Complex step_plus = std::exp(mu * dt), step_minus = std::exp(-mu * dt);
    const Complex half_mu_inv = 0.5 / mu, half_mu2_inv = 0.5 / (mu * mu);
    Complex plus = 1.0, minus = 1.0;
    Complex gram[5][5] = {};
    Complex projected[5][2] = {};
    for (Eigen::Index k = 0; k < run.size(); ++k) {
      const double t = run.t_s[static_cast<std::size_t>(k)];
      Complex c[5];
      c[0] = 0.5 * (plus + minus);
      c[1] = (plus - minus) * half_mu_inv;
      c[2] = t * c[0];
      c[3] = t * c[1];
      c[4] = (t * c[0] - c[1]) * half_mu2_inv;
      const Complex e0(run.y(0, k), run.y(1, k)), e1(run.y(2, k), run.y(3, k));
      for (int m = 0; m < 5; ++m) {
        const Complex cm = std::conj(c[m]);
        projected[m][0] += cm * e0;
        projected[m][1] += cm * e1;
        for (int n = m; n < 5; ++n) gram[m][n] += cm * c[n];
      }
      plus *= step_plus;
      minus *= step_minus;
    }
    for (auto& row : gram)
      for (const Complex& v : row) checksum += v.real();
    for (auto& row : projected) checksum += row[0].real() + row[1].imag();
  }
  return checksum;
}

}  // namespace

int main(int argc, char** argv) {
  double run_s = 100.0;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--runs-s")) {
      run_s = std::atof(argv[i + 1]);
    } else {
      std::fprintf(stderr, "unknown option %s\n", argv[i]);
      return 2;
    }
  }
  // The production design at σ = 1e-4, written as a session like the bench writes one.
  std::vector<hrgbench::estimator::RunPlan> plans;
  const double omegas[6] = {0.1, -0.1, 0.3, -0.3, 1.0, -1.0};
  for (int k = 0; k < 6; ++k) {
    hrgbench::estimator::RunPlan p;
    p.omega_rad_s = omegas[k];
    p.b = 0.1 * (k % 3);
    p.theta_rad = k * 3.141592653589793 / 12.0;
    p.sample_rate_hz = 1000.0;
    p.duration_s = run_s;
    plans.push_back(p);
  }
  hrgbench::estimator::SimulationOptions truth;
  truth.delta << -1e-3, 0.3, 2e-6, -1e-6, 3e-5, -2e-5;
  truth.xi << 0.01, -0.003, 0.002, 0.004;
  truth.sigma = 1e-4;
  const auto runs = hrgbench::estimator::SimulateRuns(plans, truth);
  const fs::path dir = fs::temp_directory_path() / "hrgbench-estimate-lower-bound";
  fs::remove_all(dir);
  hrgbench::session::Session session;
  session.serial = "BOUND";
  session.sample_rate_hz = 1000.0;
  std::size_t samples = 0;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    hrgbench::session::RunEntry entry;
    entry.id = static_cast<int>(r + 1);
    entry.file = "runs/run-00" + std::to_string(r + 1) + ".csv";
    entry.omega_rad_s = runs[r].omega_rad_s;
    session.runs.push_back(entry);
    hrgbench::session::RunSamples data;
    data.t_s = runs[r].t_s;
    data.y = runs[r].y;
    samples += data.size();
    if (!hrgbench::session::WriteRunCsv(dir / entry.file, data)) return 1;
  }
  if (!hrgbench::session::WriteSessionJson(dir, session)) return 1;

  std::vector<hrgbench::estimator::RunData> loaded;
  const double read_ms = MedianMs([&] {
    const auto s = hrgbench::session::ReadSession(dir);
    if (s) loaded = hrgbench::session::ToRunData(*s);
  });
  volatile double sink = 0.0;
  const double gram_ms = MedianMs([&] { sink = sink + GramPass(loaded); });
  const auto estimate_ms = [&](int threads) {
    hrgbench::estimator::MlOptions options;
    options.num_threads = threads;
    return MedianMs([&] {
      const auto s = hrgbench::estimator::EstimateMaximumLikelihood(loaded, options);
      sink = sink + s.delta[0];
    });
  };
  const double one_thread_ms = estimate_ms(1);
  const double all_threads_ms = estimate_ms(0);
  const double bound_ms = read_ms + 5.0 * gram_ms;
  std::printf("Production design, 6 runs × %g s at 1 kHz (%zu samples), σ = 1e-4.\n\n", run_s,
              samples);
  std::printf("| part | ms | ns per sample |\n|---|---:|---:|\n");
  const auto row = [&](const char* name, double ms) {
    std::printf("| %s | %.1f | %.1f |\n", name, ms, 1e6 * ms / static_cast<double>(samples));
  };
  row("read and parse the session", read_ms);
  row("one pass of the 5-basis Gram kernel (1 thread)", gram_ms);
  row("**bound**: read + 5 kernel passes", bound_ms);
  row("estimate, 1 thread (ML defaults)", one_thread_ms);
  row("estimate, all threads", all_threads_ms);
  std::printf(
      "\nWhole process (read + estimate, 1 thread) / bound: **%.1f×**; with all threads: "
      "%.1f×.\n",
      (read_ms + one_thread_ms) / bound_ms, (read_ms + all_threads_ms) / bound_ms);
  fs::remove_all(dir);
  return 0;
}
