#include "hrgbench/estimator/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "free_run_propagator.hpp"

namespace hrgbench::estimator {
namespace {

bool AllFinite(const Eigen::MatrixXd& m) { return m.allFinite(); }

std::uint64_t SplitMix64(std::uint64_t* state) {
  std::uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

std::uint64_t Rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

bool PlanIsValid(const RunPlan& p, std::size_t index, std::string* why) {
  const auto fail = [&](const char* what) {
    if (why) *why = "run " + std::to_string(index + 1) + ": " + what;
    return false;
  };
  if (!std::isfinite(p.omega_rad_s) || !std::isfinite(p.a) || !std::isfinite(p.b) ||
      !std::isfinite(p.theta_rad) || !std::isfinite(p.phi_rad))
    return fail("non-finite rate or orbit element");
  if (!(p.sample_rate_hz > 0.0) || !std::isfinite(p.sample_rate_hz))
    return fail("sample_rate_hz must be > 0");
  if (!(p.duration_s >= 0.0) || !std::isfinite(p.duration_s))
    return fail("duration_s must be >= 0");
  if (p.duration_s * p.sample_rate_hz > 1e9) return fail("more than 1e9 samples");
  return true;
}

}  // namespace

bool SimulationOptions::IsValid(std::string* why) const {
  if (!AllFinite(delta) || !AllFinite(xi)) {
    if (why) *why = "delta and xi must be finite";
    return false;
  }
  if (!(sigma >= 0.0) || !std::isfinite(sigma)) {
    if (why) *why = "sigma must be finite and >= 0, got " + std::to_string(sigma);
    return false;
  }
  return true;
}

NormalGenerator::NormalGenerator(std::uint64_t seed) noexcept {
  std::uint64_t sm = seed;
  for (auto& word : s_) word = SplitMix64(&sm);
}

std::uint64_t NormalGenerator::NextBits() noexcept {  // xoshiro256**
  const std::uint64_t result = Rotl(s_[1] * 5, 7) * 9;
  const std::uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = Rotl(s_[3], 45);
  return result;
}

double NormalGenerator::Next() noexcept {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  // Box–Muller on two uniforms in (0, 1]: exact up to rounding, no rejection loop.
  const double u1 = (static_cast<double>(NextBits() >> 11) + 1.0) * 0x1.0p-53;
  const double u2 = static_cast<double>(NextBits() >> 11) * 0x1.0p-53;
  const double radius = std::sqrt(-2.0 * std::log(u1));
  const double angle = 2.0 * std::numbers::pi * u2;
  spare_ = radius * std::sin(angle);
  has_spare_ = true;
  return radius * std::cos(angle);
}

State PropagateExact(double omega_rad_s, const Delta& delta, const State& x0, double t_s) noexcept {
  const internal::FreeRunPropagator propagator(omega_rad_s, delta);
  return internal::ToReal(propagator.Propagate(propagator.Scalars(t_s), internal::ToComplex(x0)));
}

std::vector<RunData> SimulateRuns(const std::vector<RunPlan>& plans,
                                  const SimulationOptions& options, std::string* why) {
  if (!options.IsValid(why)) return {};
  for (std::size_t r = 0; r < plans.size(); ++r)
    if (!PlanIsValid(plans[r], r, why)) return {};

  std::vector<RunData> runs;
  runs.reserve(plans.size());
  const internal::CMatrix2 gain = internal::PickoffGain(options.xi);
  for (std::size_t r = 0; r < plans.size(); ++r) {
    const RunPlan& plan = plans[r];
    // One independent stream per run, so adding a run never changes the noise of the others.
    NormalGenerator noise(options.seed + 0x9E3779B97F4A7C15ull * (r + 1));
    const internal::FreeRunPropagator propagator(plan.omega_rad_s, options.delta);
    const internal::CVector2 u0 =
        internal::ToComplex(OrbitToState(Orbit{plan.a, plan.b, plan.theta_rad, plan.phi_rad}));
    // Samples at k/fs for k = 0..n−1, n = round(duration·fs): a 10 s run at 100 Hz has 1000 samples
    // ending at 9.99 s, as the reference data and a capture of `duration` seconds have.
    const auto n = std::max<Eigen::Index>(
        1, static_cast<Eigen::Index>(std::llround(plan.duration_s * plan.sample_rate_hz)));
    RunData run;
    run.id = static_cast<int>(r + 1);
    run.omega_rad_s = plan.omega_rad_s;
    run.t_s.resize(static_cast<std::size_t>(n));
    run.y.resize(4, n);
    for (Eigen::Index k = 0; k < n; ++k) {
      const double t = static_cast<double>(k) / plan.sample_rate_hz;
      run.t_s[static_cast<std::size_t>(k)] = t;
      const internal::CVector2 y = gain * propagator.Propagate(propagator.Scalars(t), u0);
      Eigen::Vector4d yk = internal::ToReal(y);
      if (options.sigma > 0.0)
        for (int c = 0; c < 4; ++c) yk[c] += options.sigma * noise.Next();
      run.y.col(k) = yk;
    }
    runs.push_back(std::move(run));
  }
  return runs;
}

}  // namespace hrgbench::estimator
