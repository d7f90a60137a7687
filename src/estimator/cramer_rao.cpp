#include "hrgbench/estimator/cramer_rao.hpp"

#include <cmath>
#include <limits>

#include "hrgbench/estimator/model.hpp"
#include "hrgbench/estimator/simulation.hpp"
#include "least_squares_util.hpp"
#include "output_error_problem.hpp"

namespace hrgbench::estimator {

bool DesignSpec::IsValid(std::string* why) const {
  if (!(sigma > 0.0) || !std::isfinite(sigma)) {
    if (why) *why = "sigma must be finite and > 0, got " + std::to_string(sigma);
    return false;
  }
  if (runs.empty()) {
    if (why) *why = "the design has no runs";
    return false;
  }
  if (phase_degree < 0 || phase_degree > 3) {
    if (why) *why = "phase_degree must be 0 ... 3, got " + std::to_string(phase_degree);
    return false;
  }
  SimulationOptions truth;
  truth.delta = delta;
  truth.xi = xi;
  return truth.IsValid(why);
}

CrlbResult CramerRaoBound(const DesignSpec& design, const IdentifiabilityOptions& options) {
  CrlbResult result;
  std::string why;
  if (!design.IsValid(&why) || !options.IsValid(&why)) {
    result.message = why;
    return result;
  }
  SimulationOptions truth;
  truth.delta = design.delta;
  truth.xi = design.xi;
  truth.sigma = 0.0;
  const std::vector<RunData> runs = SimulateRuns(design.runs, truth, &why);
  if (runs.empty()) {
    result.message = why;
    return result;
  }
  for (const RunData& r : runs) result.samples += static_cast<std::size_t>(r.size());
  if (result.samples / runs.size() < 2) {
    result.message = "every run needs at least 2 samples";
    return result;
  }
  std::vector<double> omegas;
  for (const RunPlan& r : design.runs) omegas.push_back(r.omega_rad_s);
  result.identifiability = CheckRatePlan(omegas, design.xi_unknown, options);
  std::array<bool, 6> delta_free = result.identifiability.delta_identifiable;
  XiMask xi_free = result.identifiability.IdentifiableXi(design.xi_unknown);

  internal::NuisanceModel model;
  model.phase_degree = design.phase_degree;
  const internal::FullParameters p = internal::Pack(design.delta, design.xi);
  std::vector<internal::RunNuisance> x0;
  for (const RunPlan& r : design.runs) {
    internal::RunNuisance n = internal::RunNuisance::Zero(model.Size(x0.size()));
    n.head<4>() =
        internal::ObservedInitialState(p, OrbitToState(Orbit{r.a, r.b, r.theta_rad, r.phi_rad}));
    x0.push_back(n);
  }
  Eigen::MatrixXd information;
  std::vector<int> indices;
  for (;;) {
    indices.clear();
    for (int j = 0; j < 6; ++j)
      if (delta_free[j]) indices.push_back(j);
    for (int k = 0; k < 4; ++k)
      if (xi_free[k]) indices.push_back(internal::kXiOffset + k);
    const RunsInMemory run_set(runs);
    internal::OutputErrorProblem problem(run_set, indices, 1, 0, model);
    internal::NormalEquations ne;
    problem.Linearize(p, x0, &ne);
    if (indices.empty() || !internal::ReducedInformation(ne, &information)) break;
    CheckInformation(information, delta_free, xi_free, options, &result.identifiability);
    const std::array<bool, 6> delta_now = result.identifiability.delta_identifiable;
    const XiMask xi_now = result.identifiability.IdentifiableXi(xi_free);
    if (delta_now == delta_free && xi_now == xi_free) break;
    delta_free = delta_now;
    xi_free = xi_now;
  }
  // Unidentifiable parameters have an infinite bound; the others are bounded with those held.
  const double inf = std::numeric_limits<double>::infinity();
  for (int j = 0; j < 6; ++j) result.delta_std[j] = delta_free[j] ? kNaN : inf;
  for (int k = 0; k < 4; ++k)
    result.xi_std[k] = design.xi_unknown[k] ? (xi_free[k] ? kNaN : inf) : kNaN;
  Eigen::MatrixXd inverse;
  if (!indices.empty()) {
    if (!internal::InvertScaledSpd(information, &inverse)) {
      result.message = "the information matrix is singular";
      return result;
    }
    result.covariance = (design.sigma * design.sigma) * inverse;
    for (std::size_t c = 0; c < indices.size(); ++c) {
      const auto i = static_cast<Eigen::Index>(c);
      const double sd = std::sqrt(std::max(0.0, result.covariance(i, i)));
      if (indices[c] < internal::kXiOffset)
        result.delta_std[indices[c]] = sd;
      else
        result.xi_std[indices[c] - internal::kXiOffset] = sd;
    }
  }
  result.valid = true;
  result.message = result.identifiability.reasons.empty()
                       ? "every requested parameter is identifiable"
                       : result.identifiability.reasons.front();
  return result;
}

}  // namespace hrgbench::estimator
