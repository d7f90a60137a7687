#include "hrgbench/estimator/fitted_output.hpp"

#include <cmath>
#include <complex>

#include "common_phase.hpp"
#include "free_run_propagator.hpp"

namespace hrgbench::estimator {
namespace {

const RunNuisanceEstimate* FindNuisance(const EstimateSummary& summary, int run_id) {
  for (const RunNuisanceEstimate& n : summary.run_nuisance)
    if (n.run_id == run_id) return &n;
  return nullptr;
}

RunChannels Evaluate(const EstimateSummary& summary, const RunData& run, bool distorted) {
  const RunNuisanceEstimate* n = FindNuisance(summary, run.id);
  if (n == nullptr || !summary.delta.allFinite() || !summary.xi.allFinite() ||
      !n->initial_state.allFinite() || n->phase_coefficients.size() >
                                           static_cast<std::size_t>(internal::kMaxPhaseDegree))
    return RunChannels(0, 4);
  const internal::FreeRunPropagator propagator(run.omega_rad_s + n->omega_offset_rad_s,
                                               summary.delta);
  const internal::CMatrix2 gain =
      distorted ? internal::PickoffGain(summary.xi) : internal::CMatrix2::Identity();
  const internal::CVector2 u0 = internal::ToComplex(n->initial_state);
  // ψ in closed form at each time stamp: the fit's recurrence agrees with it to ~1e-14, and a
  // report evaluates runs once.
  const internal::CommonPhase phase(n->phase_coefficients.data(),
                                    static_cast<int>(n->phase_coefficients.size()));
  RunChannels out(static_cast<Eigen::Index>(run.t_s.size()), 4);
  for (std::size_t k = 0; k < run.t_s.size(); ++k) {
    const double t = run.t_s[k];
    const internal::CVector2 v = propagator.Propagate(propagator.Scalars(t), u0);
    const internal::CVector2 y = std::polar(1.0, phase.Psi(t)) * (gain * v);
    out.row(static_cast<Eigen::Index>(k)) = internal::ToReal(y).transpose();
  }
  return out;
}

}  // namespace

RunChannels FittedOutput(const EstimateSummary& summary, const RunData& run) {
  return Evaluate(summary, run, true);
}

RunChannels FittedState(const EstimateSummary& summary, const RunData& run) {
  return Evaluate(summary, run, false);
}

}  // namespace hrgbench::estimator
