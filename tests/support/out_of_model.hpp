#pragma once
// What a real bench does that the estimator's model does not: the perturbations of the issue's
// table, applied to runs simulated by the model (estimator::SimulateRuns with σ = 0, then the
// perturbation, then the noise). Written from their definitions, without the estimator's
// propagator: a common phase multiplies both complex channels u = (y1 + i·y2, y3 + i·y4) by
// e^{iψ(t)}, AR(1) noise is x_k = ρ·x_{k−1} + √(1−ρ²)·σ·n_k per channel, a spike adds ±A·σ to one
// channel of one sample.
//
// Used by the out-of-model tests and by benchmarks/out_of_model_table.

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "hrgbench/estimator/parameters.hpp"
#include "hrgbench/estimator/run_data.hpp"
#include "hrgbench/estimator/simulation.hpp"

namespace hrgbench::testing {

// The production design (README): 6 runs at Ω = ±0.1, ±0.3, ±1 rad/s, θ = kπ/12, a = 1,
// b = 0.1·(−1)^k.
inline std::vector<estimator::RunPlan> ProductionPlans(double duration_s, double sample_rate_hz) {
  const double omegas[6] = {0.1, -0.1, 0.3, -0.3, 1.0, -1.0};
  std::vector<estimator::RunPlan> plans;
  for (int k = 0; k < 6; ++k) {
    estimator::RunPlan p;
    p.omega_rad_s = omegas[k];
    p.a = 1.0;
    p.b = (k % 2 == 0 ? 0.1 : -0.1);
    p.theta_rad = k * M_PI / 12.0;
    p.sample_rate_hz = sample_rate_hz;
    p.duration_s = duration_s;
    plans.push_back(p);
  }
  return plans;
}

// A resonator like the README's production example: τ ≈ 1000 s, small anisotropies, all four ξ.
inline estimator::SimulationOptions ProductionTruth() {
  estimator::SimulationOptions truth;
  truth.delta << -1e-3, 0.3, 2e-6, -1e-6, 3e-5, -2e-5;
  truth.xi << 0.01, -0.003, 0.002, 0.004;
  return truth;
}

// Multiplies both complex channels of every sample by e^{iψ(t)}.
template <typename Psi>
void ApplyCommonPhase(estimator::RunData* run, Psi psi) {
  for (Eigen::Index k = 0; k < run->size(); ++k) {
    const double phase = psi(run->t_s[static_cast<std::size_t>(k)]);
    const double c = std::cos(phase), s = std::sin(phase);
    for (int channel = 0; channel < 2; ++channel) {
      const double re = run->y(2 * channel, k), im = run->y(2 * channel + 1, k);
      run->y(2 * channel, k) = c * re - s * im;
      run->y(2 * channel + 1, k) = s * re + c * im;
    }
  }
}

// A common frequency that ramps linearly from 0 to `end_rad_s` over the run: ψ = ½·(end/T)·t².
inline void ApplyFrequencyRamp(estimator::RunData* run, double end_rad_s) {
  const double duration = run->t_s.back() - run->t_s.front();
  const double rate = end_rad_s / duration;
  ApplyCommonPhase(run, [rate](double t) { return 0.5 * rate * t * t; });
}

// Adds white (ρ = 0) or AR(1) Gaussian noise of marginal std σ to every channel.
inline void AddNoise(estimator::RunData* run, double sigma, double rho, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double innovation = std::sqrt(1.0 - rho * rho) * sigma;
  for (int c = 0; c < 4; ++c) {
    double state = sigma * normal(engine);
    for (Eigen::Index k = 0; k < run->size(); ++k) {
      if (k > 0) state = rho * state + innovation * normal(engine);
      run->y(c, k) += state;
    }
  }
}

// Adds `count` spikes of ±amplitude (in the same unit as y) at distinct random samples and
// channels.
inline void AddSpikes(estimator::RunData* run, int count, double amplitude, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  std::uniform_int_distribution<Eigen::Index> sample(0, run->size() - 1);
  std::uniform_int_distribution<int> channel(0, 3);
  for (int i = 0; i < count; ++i) {
    const double sign = (engine() & 1) ? 1.0 : -1.0;
    run->y(channel(engine), sample(engine)) += sign * amplitude;
  }
}

}  // namespace hrgbench::testing
