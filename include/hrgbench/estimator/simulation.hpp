#pragma once
// Exact simulation of free runs. The dynamics is linear with constant coefficients, so each sample
// is x(t) = exp(A(Ω, δ)·t)·x(0), evaluated in closed form for every time stamp (no integration
// error, no accumulation over long runs); y = (I + C(ξ))·x plus independent Gaussian noise of std σ
// per channel.
//
// The noise generator is part of this library (xoshiro256** with a Box–Muller transform), so a seed
// gives the same data on every platform and standard library.

#include <cstdint>
#include <string>
#include <vector>

#include "hrgbench/estimator/model.hpp"
#include "hrgbench/estimator/run_data.hpp"

namespace hrgbench::estimator {

struct SimulationOptions {
  Delta delta = Delta::Zero();
  Xi xi = Xi::Zero();
  double sigma = 0.0;      // noise std on each channel of y, same unit as y; 0 = noise-free
  std::uint64_t seed = 1;  // runs use consecutive sub-streams of this seed, in order

  bool IsValid(std::string* why) const;
};

// Simulates every planned run. Returns an empty vector when the options or a plan are invalid
// (non-finite values, σ < 0, sample rate ≤ 0, duration < 0); `why` (optional) then says which.
std::vector<RunData> SimulateRuns(const std::vector<RunPlan>& plans,
                                  const SimulationOptions& options, std::string* why = nullptr);

// Noise-free state at time t [s] of a free run released at x0 at t = 0 (closed-form exp(A·t)·x0).
State PropagateExact(double omega_rad_s, const Delta& delta, const State& x0, double t_s) noexcept;

// Deterministic standard normal generator, portable across platforms.
class NormalGenerator {
 public:
  explicit NormalGenerator(std::uint64_t seed) noexcept;
  double Next() noexcept;

 private:
  std::uint64_t NextBits() noexcept;
  std::uint64_t s_[4];
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace hrgbench::estimator
