#include "hrgbench/estimator/maximum_likelihood.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include "cleaned_runs.hpp"
#include "common_phase.hpp"
#include "common_phase_start.hpp"
#include "hrgbench/estimator/iq_convention.hpp"
#include "integral_equation_error.hpp"
#include "least_squares_util.hpp"
#include "output_error_problem.hpp"
#include "parallel_for.hpp"

namespace hrgbench::estimator {
namespace {

using internal::FullParameters;

// Samples per run the starting points' initial states are solved from
// (OutputErrorProblem::SolveInitialStates): enough to tell two starting points apart, and a w0 a
// Gauss–Newton step finishes exactly; a production run's 100 000 samples are 12 times that.
constexpr Eigen::Index kStartSamplesPerRun = 8192;

// What is estimated after the identifiability rules, and the values of what is held.
struct FreeSet {
  std::array<bool, 6> delta = {};
  XiMask xi = kNoXi;
  Delta delta_fixed = Delta::Zero();
  Xi xi_fixed = Xi::Zero();

  std::vector<int> Indices() const {
    std::vector<int> out;
    for (int j = 0; j < 6; ++j)
      if (delta[j]) out.push_back(j);
    for (int k = 0; k < 4; ++k)
      if (xi[k]) out.push_back(internal::kXiOffset + k);
    return out;
  }
};

// Validates, applies the rate-plan rules. Returns false (summary filled) when the estimate must
// not go ahead.
bool Prepare(const RunSet& runs, const MlOptions& options, EstimateSummary* s, FreeSet* free) {
  std::string why;
  if (!options.IsValid(&why) ||
      !internal::ValidateRunData(runs, static_cast<std::size_t>(kMlMinimumSamples), &why)) {
    s->termination = Termination::kInvalidInput;
    s->message = why;
    return false;
  }
  std::vector<double> omegas;
  for (std::size_t r = 0; r < runs.size(); ++r) omegas.push_back(runs.Info(r).omega_rad_s);
  const IdentifiabilityReport rules =
      CheckRatePlan(omegas, options.xi_estimated, options.identifiability);
  free->delta_fixed = options.delta_fixed;
  free->xi_fixed = options.xi_fixed;
  for (int j = 0; j < 6; ++j)
    free->delta[j] = options.delta_estimated[j] && rules.delta_identifiable[j];
  free->xi = rules.IdentifiableXi(options.xi_estimated);
  const bool lost = free->delta != options.delta_estimated || free->xi != options.xi_estimated;
  if (lost && options.unidentifiable == UnidentifiablePolicy::kRefuse) {
    s->termination = Termination::kNotIdentifiable;
    s->message = rules.reasons.empty() ? "the plan cannot determine the requested parameters"
                                       : rules.reasons.front();
    s->warnings = rules.reasons;
    return false;
  }
  for (const std::string& reason : rules.reasons) s->warnings.push_back(reason);
  return true;
}

void FillParameters(const FullParameters& p, const FreeSet& free, EstimateSummary* s) {
  s->delta = p.head<6>();
  s->xi = p.tail<4>();
  s->delta_estimated = free.delta;
  s->xi_estimated = free.xi;
}

// σ̂²·H_red⁻¹ into the summary's covariance and std.
// `covariance` (of the free parameters, in `indices` order) into the summary, and each one's std.
void SetCovariance(const Eigen::MatrixXd& covariance, const std::vector<int>& indices,
                   EstimateSummary* s) {
  s->covariance = covariance;
  for (std::size_t c = 0; c < indices.size(); ++c) {
    const auto i = static_cast<Eigen::Index>(c);
    const double sd = std::sqrt(std::max(0.0, covariance(i, i)));
    if (indices[c] < internal::kXiOffset)
      s->delta_std[indices[c]] = sd;
    else
      s->xi_std[indices[c] - internal::kXiOffset] = sd;
  }
}

void FillCovariance(const Eigen::MatrixXd& h_reduced, const std::vector<int>& indices, double s2,
                    EstimateSummary* s) {
  Eigen::MatrixXd inverse;
  s->delta_std = Delta::Constant(kNaN);
  s->xi_std = Xi::Constant(kNaN);
  if (indices.empty() || !internal::InvertScaledSpd(h_reduced, &inverse)) {
    if (!indices.empty()) s->warnings.push_back("information matrix singular: no covariance");
    return;
  }
  SetCovariance(s2 * inverse, indices, s);
}

bool StepSmall(const Eigen::VectorXd& step, const Eigen::MatrixXd& h_reduced, double s2,
               double tolerance_in_std) {
  Eigen::MatrixXd inverse;
  if (!internal::InvertScaledSpd(h_reduced, &inverse)) return false;
  for (Eigen::Index i = 0; i < step.size(); ++i) {
    const double sd = std::sqrt(std::max(0.0, s2 * inverse(i, i)));
    if (!(std::abs(step[i]) <= tolerance_in_std * sd)) return false;
  }
  return true;
}

}  // namespace

bool MlOptions::IsValid(std::string* why) const {
  const auto fail = [why](std::string text) {
    if (why) *why = std::move(text);
    return false;
  };
  if (max_iterations < 1) return fail("max_iterations must be >= 1");
  if (num_threads < 0) return fail("num_threads must be >= 0");
  if (!(step_tolerance_in_std > 0.0)) return fail("step_tolerance_in_std must be > 0");
  if (!(cost_tolerance >= 0.0)) return fail("cost_tolerance must be >= 0");
  if (!(initial_damping >= 0.0)) return fail("initial_damping must be >= 0");
  if (!xi_fixed.allFinite() || !delta_fixed.allFinite()) return fail("fixed values must be finite");
  if (use_initial_guess && (!initial_delta.allFinite() || !initial_xi.allFinite()))
    return fail("the initial guess must be finite");
  if (phase_degree < 0 || phase_degree > internal::kMaxPhaseDegree)
    return fail("phase_degree must be 0 ... 3");
  if (!(outlier_threshold_sigma >= 0.0)) return fail("outlier_threshold_sigma must be >= 0");
  if (max_outlier_passes < 0 || max_outlier_passes > 10)
    return fail("max_outlier_passes must be 0 ... 10");
  if (whiteness_lags < 1 || whiteness_lags > 1000) return fail("whiteness_lags must be 1 ... 1000");
  if (!fit_quality.IsValid(why)) return false;
  if (!noise_shape.IsValid(why)) return false;
  return identifiability.IsValid(why);
}

EstimateSummary EstimateIntegralEquationError(const std::vector<RunData>& runs_in_memory,
                                              const MlOptions& options) {
  const RunsInMemory runs(runs_in_memory);
  EstimateSummary s;
  s.method = "integral-equation-error";
  s.message.clear();
  FreeSet free;
  if (!Prepare(runs, options, &s, &free)) return s;
  internal::IntegralEquationResult iee;
  iee.want_sse = true;
  if (!internal::IntegralEquationError(runs, free.delta, free.delta_fixed, free.xi, free.xi_fixed,
                                       &iee)) {
    s.termination = Termination::kNumericalFailure;
    s.message = "the integral equation-error regression is singular";
    return s;
  }
  FillParameters(internal::Pack(iee.delta, iee.xi), free, &s);
  s.iterations = 1;
  s.samples_used = runs.TotalSamples();
  s.residual_rms =
      std::sqrt(iee.sse / static_cast<double>(4 * std::max<std::size_t>(1, iee.equations)));
  s.termination = Termination::kConverged;
  s.message = "integral equation error (starting point of ml); no std reported";
  return s;
}

namespace {

// Where one fit ended: the parameters, every run's nuisance, and the normal equations there.
struct FitState {
  FullParameters p;
  std::vector<internal::RunNuisance> nuisance;
  internal::NormalEquations ne;
  std::vector<int> indices;
  double dof = 1.0;
  int threads = 1;
  // True when the last step was taken without linearising at its end (see the quadratic-convergence
  // test in Fit): `ne` is then the linearisation one small step before p, and its cost is not p's
  // (the residual pass replaces it).
  bool ne_one_step_behind = false;
};

// The largest |step_i| in units of its std, σ̂²·H_red⁻¹; NaN when H_red is singular.
double StepInStd(const Eigen::VectorXd& step, const Eigen::MatrixXd& h_reduced, double s2) {
  Eigen::MatrixXd inverse;
  if (!internal::InvertScaledSpd(h_reduced, &inverse)) return kNaN;
  double largest = 0.0;
  for (Eigen::Index i = 0; i < step.size(); ++i)
    largest = std::max(largest, std::abs(step[i]) / std::sqrt(std::max(0.0, s2 * inverse(i, i))));
  return largest;
}

// Steps 1–3 of the header on `runs`. Fills termination, message, warnings and iterations of `s`;
// false when no estimate could be made.
// `start`, `start_nuisance_seed`: where a previous fit of the same runs (before outliers were
// removed) ended; its common phases and Ω offsets seed this one (w0 is solved again).
bool Fit(const RunSet& runs, const MlOptions& options, const internal::NuisanceModel& model,
         const FullParameters* start, const std::vector<internal::RunNuisance>* start_nuisance_seed,
         FreeSet* free, FitState* state, EstimateSummary* s) {
  // 1. Starting point.
  FullParameters& p = state->p;
  // The initial states solved for the chosen starting point (from kStartSamplesPerRun samples of
  // each run), when the start was chosen by cost: step 2 linearises there.
  std::vector<internal::RunNuisance> start_nuisance;
  // The nuisance to start from when start_nuisance is not (w0 unsolved): the common phase of each
  // run from the data (common_phase_start.hpp), or a previous fit's.
  std::vector<internal::RunNuisance> seed_nuisance;
  if (start != nullptr) {
    p = *start;
    if (start_nuisance_seed != nullptr) seed_nuisance = *start_nuisance_seed;
  } else if (options.use_initial_guess) {
    p = internal::Pack(options.initial_delta, options.initial_xi);
    if (options.common_phase_start_from_data)
      seed_nuisance = internal::StartNuisance(
          runs, p, model,
          internal::OutputErrorProblem(runs, {}, options.num_threads,
                                       options.min_samples_for_threads, model)
              .Threads());
  } else {
    // Two starting points from the integral equation error: with ξ through its first-order effect,
    // and with ξ held at its given value (physically |ξ| ≪ 1). On strong designs the first is
    // within rounding of the optimum; on weak ones (the paper's: condition ~3e4) under noise it can
    // land at |ξ| ~ 0.4, outside the region where the model is nearly linear in ξ. The output-error
    // cost itself decides between them.
    p = internal::Pack(free->delta_fixed, free->xi_fixed);
    double best_cost = std::numeric_limits<double>::infinity();
    const internal::OutputErrorProblem start_problem(runs, {}, options.num_threads,
                                                     options.min_samples_for_threads, model);
    // Both candidates' regressions share one pass over the data when they hold the same ξ.
    internal::IntegralEquationSums iee_sums;
    struct Candidate {
      FullParameters p;
      std::vector<internal::RunNuisance> nuisance;
      internal::InitialStatesCost cost;
    };
    std::vector<Candidate> candidates;
    for (const XiMask& xi_in_start : {free->xi, kNoXi}) {
      internal::IntegralEquationResult iee;
      // Each run's initial forms unknown and the integral end-corrected: a start whose error,
      // in units of the fit's std, no longer grows with the runs' length (IntegralEquationError).
      iee.initial_forms_free = true;
      if (internal::IntegralEquationError(runs, free->delta, free->delta_fixed, xi_in_start,
                                          free->xi_fixed, &iee, start_problem.Threads(),
                                          &iee_sums)) {
        // The ξ found to first order removed exactly and corrected: the start's δ2 then no longer
        // drifts with the runs' length (RefinedIntegralEquationError). From the same sums: no
        // pass over the data.
        if (xi_in_start != kNoXi)
          internal::RefinedIntegralEquationError(runs, free->delta, free->delta_fixed, xi_in_start,
                                                 iee, &iee, start_problem.Threads(), &iee_sums);
        Candidate c;
        c.p = internal::Pack(iee.delta, iee.xi);
        // The integral equation error does not see the common phase (its forms discard it): each
        // run's ψ is started from the data at this candidate's (δ, ξ), not at zero, which on long
        // runs with a reference offset and a drift lands in a wrong basin. Per candidate: on a
        // weak design the candidate with ξ in can be far off (|ξ| ~ 0.4), and its distortion would
        // spoil the other's phase.
        if (options.common_phase_start_from_data)
          c.nuisance = internal::StartNuisance(runs, c.p, model, start_problem.Threads());
        if (start_problem.SolveInitialStates(c.p, &c.nuisance, &c.cost, kStartSamplesPerRun))
          candidates.push_back(std::move(c));
      }
      if (xi_in_start == kNoXi) break;
    }
    // The cost at the solved initial states (over the samples they were solved from) follows from
    // their normal equations (Σ|y|² − b^H·u0), exact up to cancellation against Σ|y|²: when the two
    // candidates' costs differ by far more than that, it decides without a cost pass over the data;
    // otherwise (noise-free data, a tie) the cost passes do, as they always did.
    std::size_t best = candidates.size();
    if (candidates.size() == 1 && std::isfinite(candidates[0].cost.cost)) {
      best = 0;  // nothing to choose between
      best_cost = candidates[0].cost.cost;
    } else if (candidates.size() == 2) {
      const internal::InitialStatesCost& a = candidates[0].cost;
      const internal::InitialStatesCost& b = candidates[1].cost;
      const double margin = 1e-9 * std::max(a.data_norm2, b.data_norm2);
      if (std::isfinite(a.cost) && std::isfinite(b.cost) && std::abs(a.cost - b.cost) > margin) {
        best = a.cost <= b.cost ? 0 : 1;
        best_cost = candidates[best].cost.cost;
      }
    }
    if (best == candidates.size()) {
      for (std::size_t c = 0; c < candidates.size(); ++c) {
        const double cost = start_problem.Cost(candidates[c].p, candidates[c].nuisance);
        if (cost < best_cost) {
          best_cost = cost;
          best = c;
        }
      }
    }
    if (best < candidates.size()) {
      p = candidates[best].p;
      start_nuisance = std::move(candidates[best].nuisance);
    }
    if (!std::isfinite(best_cost)) {
      s->termination = Termination::kNumericalFailure;
      s->message = "the starting point (integral equation error) is singular";
      return false;
    }
  }
  const FullParameters chosen = p;
  for (int j = 0; j < 6; ++j)
    if (!free->delta[j]) p[j] = free->delta_fixed[j];
  for (int k = 0; k < 4; ++k)
    if (!free->xi[k]) p[internal::kXiOffset + k] = free->xi_fixed[k];
  std::vector<internal::RunNuisance>& x0 = state->nuisance;
  x0.clear();
  bool x0_current = !start_nuisance.empty() && p == chosen;
  if (x0_current) {
    x0 = std::move(start_nuisance);
  } else {
    // Solved below for p; the common phase and ΔΩ they hold are kept.
    x0 = start_nuisance.empty() ? std::move(seed_nuisance) : std::move(start_nuisance);
    if (x0.size() != runs.size()) x0.clear();
  }

  // 2. Numerical identifiability at the starting point; drop what the data cannot determine.
  internal::NormalEquations& ne = state->ne;
  std::vector<int>& indices = state->indices;
  indices = free->Indices();
  for (;;) {
    internal::OutputErrorProblem problem(runs, indices, options.num_threads,
                                         options.min_samples_for_threads, model);
    if (!x0_current && !problem.SolveInitialStates(p, &x0)) {
      s->termination = Termination::kNumericalFailure;
      s->message = "initial states cannot be solved for: a run carries no signal";
      return false;
    }
    problem.Linearize(p, x0, &ne);
    Eigen::MatrixXd h_reduced;
    if (indices.empty() || !internal::ReducedInformation(ne, &h_reduced)) break;
    IdentifiabilityReport numeric;
    const std::array<bool, 6> delta_before = free->delta;
    const XiMask xi_before = free->xi;
    const double condition =
        CheckInformation(h_reduced, free->delta, free->xi, options.identifiability, &numeric);
    for (int j = 0; j < 6; ++j) free->delta[j] = free->delta[j] && numeric.delta_identifiable[j];
    free->xi = numeric.IdentifiableXi(free->xi);
    if (free->delta == delta_before && free->xi == xi_before) {
      if (condition > 1e6) {
        char buffer[200];
        std::snprintf(buffer, sizeof buffer,
                      "weakly determined parameters: scaled information condition %.2g "
                      "(more distinct or larger rates would help)",
                      condition);
        s->warnings.emplace_back(buffer);
      }
      break;
    }
    for (const std::string& reason : numeric.reasons) s->warnings.push_back(reason);
    if (options.unidentifiable == UnidentifiablePolicy::kRefuse) {
      s->termination = Termination::kNotIdentifiable;
      s->message = numeric.reasons.empty() ? "not identifiable" : numeric.reasons.front();
      return false;
    }
    for (int j = 0; j < 6; ++j)
      if (!free->delta[j]) p[j] = free->delta_fixed[j];
    for (int k = 0; k < 4; ++k)
      if (!free->xi[k]) p[internal::kXiOffset + k] = free->xi_fixed[k];
    indices = free->Indices();
    x0_current = false;
  }
  const internal::OutputErrorProblem problem(runs, indices, options.num_threads,
                                             options.min_samples_for_threads, model);
  const auto n_obs = static_cast<double>(problem.NumObservations());
  state->dof = std::max(1.0, n_obs - static_cast<double>(indices.size()) -
                                 static_cast<double>(problem.NumNuisanceDegreesOfFreedom()));
  const double dof = state->dof;
  double y_scale2 = 0.0;
  for (std::size_t r = 0; r < runs.size(); ++r) y_scale2 += runs.Load(r)->y.squaredNorm();
  // Below this cost the residual is rounding noise of the model evaluation: nothing left to fit.
  const double cost_floor = 1e-28 * y_scale2;

  // 3. Levenberg–Marquardt, one linearisation per iteration (the trial point's linearisation is the
  // next iteration's when accepted).
  double lambda = options.initial_damping;
  state->ne_one_step_behind = false;
  // The previous iteration's accepted step, in std (NaN: none yet, or it was damped after a
  // rejection).
  double previous_step_std = kNaN;
  s->termination = Termination::kMaxIterations;
  s->message = "stopped at max_iterations";
  int iteration = 0;
  for (; iteration < options.max_iterations; ++iteration) {
    if (ne.cost <= cost_floor) {
      s->termination = Termination::kConverged;
      s->message = "residual at rounding level";
      break;
    }
    Eigen::VectorXd dp;
    std::vector<internal::RunNuisance> dx0;
    internal::NormalEquations trial;
    FullParameters p_trial;
    std::vector<internal::RunNuisance> x0_trial(x0.size());
    bool accepted = false;
    bool linearized = false;
    // The first trial of an iteration is usually accepted, so it is linearised at once (its normal
    // equations are the next iteration's); after a rejection, trials are only costed (a Cost pass
    // is ~60 % of a Linearize pass) and the accepted one is linearised once.
    bool first_trial = true;
    double cost_by_cost_pass = kNaN;
    bool converged_here = false;
    bool converged_unconfirmed = false;
    double step_std = kNaN;
    while (lambda <= 1e12) {
      if (internal::SolveDamped(ne, lambda, &dp, &dx0)) {
        // Gauss–Newton's own convergence test, before any pass over the data: when the step the
        // linearisation at p predicts is already below tolerance, p is the minimum to within it.
        // Near the minimum a trial's cost differs from the current one by rounding only, so trying
        // it would cost one or more passes and, when rounding goes the wrong way, a ladder of
        // rejected steps.
        Eigen::MatrixXd h_now;
        const bool have_h_now = first_trial && internal::ReducedInformation(ne, &h_now);
        if (have_h_now && iteration > 0 &&
            StepSmall(dp, h_now, ne.cost / dof, options.step_tolerance_in_std)) {
          converged_here = true;
          break;
        }
        p_trial = p;
        for (std::size_t c = 0; c < indices.size(); ++c)
          p_trial[indices[c]] += dp[static_cast<Eigen::Index>(c)];
        for (std::size_t r = 0; r < x0.size(); ++r) x0_trial[r] = x0[r] + dx0[r];
        // Gauss–Newton converges quadratically: with steps ε_{k−1}, ε_k (in std), the next is
        // ≈ κ·ε_k² with κ = ε_k/ε_{k−1}², and κ·ε_k is the relative change of the Jacobian over
        // this step. When the next step is predicted far below tolerance and the information at
        // p_trial differs from that at p by far less than the std's own digits, the step is taken
        // without the linearisation that would only confirm it (a whole pass): the estimate is
        // the same point, its covariance comes from p's information (relative error ~κ·ε_k), and
        // its cost from the residual pass that follows every fit.
        if (have_h_now) step_std = StepInStd(dp, h_now, ne.cost / dof);
        if (have_h_now && std::isfinite(previous_step_std) && previous_step_std > 0.0) {
          const double kappa = step_std / (previous_step_std * previous_step_std);
          if (std::isfinite(kappa) &&
              kappa * step_std * step_std <= 1e-2 * options.step_tolerance_in_std &&
              kappa * step_std <= 1e-8) {
            converged_unconfirmed = true;
            break;
          }
        }
        double trial_cost;
        double reference_cost = ne.cost;
        if (first_trial) {
          problem.Linearize(p_trial, x0_trial, &trial);
          trial_cost = trial.cost;
        } else {
          // Compare like with like: the two passes sum the same residuals in different order and
          // form, and near the optimum their last digits decide acceptance.
          if (!std::isfinite(cost_by_cost_pass)) cost_by_cost_pass = problem.Cost(p, x0);
          reference_cost = cost_by_cost_pass;
          trial_cost = problem.Cost(p_trial, x0_trial);
        }
        linearized = first_trial;
        first_trial = false;
        if (std::isfinite(trial_cost) && trial_cost <= reference_cost) {
          accepted = true;
          break;
        }
      }
      lambda = std::max(lambda * 10.0, 1e-9);
    }
    if (converged_here) {
      s->termination = Termination::kConverged;
      s->message = "step below tolerance (in units of std)";
      break;
    }
    if (converged_unconfirmed) {
      p = p_trial;
      x0 = x0_trial;
      state->ne_one_step_behind = true;
      ++iteration;
      s->termination = Termination::kConverged;
      s->message = "step below tolerance (in units of std)";
      break;
    }
    if (accepted && !linearized) problem.Linearize(p_trial, x0_trial, &trial);
    if (!accepted) {
      s->termination = Termination::kNoProgress;
      s->message = "no step reduces the cost (at the minimum up to rounding)";
      break;
    }
    const double decrease = (ne.cost - trial.cost) / std::max(ne.cost, 1e-300);
    p = p_trial;
    x0 = x0_trial;
    ne = std::move(trial);
    lambda = std::max(lambda * 0.1, 1e-12);
    previous_step_std = linearized ? step_std : kNaN;
    Eigen::MatrixXd h_reduced;
    const double s2 = ne.cost / dof;
    if (decrease <= options.cost_tolerance ||
        (internal::ReducedInformation(ne, &h_reduced) &&
         StepSmall(dp, h_reduced, s2, options.step_tolerance_in_std))) {
      ++iteration;
      s->termination = Termination::kConverged;
      s->message = decrease <= options.cost_tolerance ? "relative cost decrease below tolerance"
                                                      : "step below tolerance (in units of std)";
      break;
    }
  }
  s->iterations += iteration;
  state->threads = problem.Threads();
  if (s->termination == Termination::kNoProgress && ne.cost <= 1e3 * cost_floor) {
    s->termination = Termination::kConverged;
    s->message = "residual at rounding level";
  }
  return true;
}

std::string Format(const char* format, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char buffer[320];
  std::snprintf(buffer, sizeof buffer, format, a, b, c, d);
  return buffer;
}

// The noise the data carry, from the data alone (4th differences of y, model-free): per run, and
// pooled over the runs' samples. It weighs the priors on Ω, and the residuals are judged against
// it.
struct DataNoise {
  std::vector<double> sigma;  // per run; NaN once a run's samples change (outliers removed)
  double pooled = kNaN;
};

DataNoise MeasureDataNoise(const RunSet& runs, const DifferenceNoiseModel& difference_noise,
                           std::size_t samples) {
  DataNoise noise;
  noise.sigma.resize(runs.size());
  double noise_sum2 = 0.0;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    noise.sigma[r] = DifferenceNoiseSigma(runs.Load(r)->y, difference_noise);
    if (std::isfinite(noise.sigma[r]))
      noise_sum2 += noise.sigma[r] * noise.sigma[r] * static_cast<double>(runs.Info(r).samples);
  }
  noise.pooled = std::sqrt(noise_sum2 / static_cast<double>(samples));
  return noise;
}

// The runs' nuisance: the common phase's degree, and each run's Ω offset with its prior weight
// (σ̂² / σ_Ω²) when the run records a standard error of Ω and its use is on.
internal::NuisanceModel NuisanceModelFor(const RunSet& runs, const MlOptions& options,
                                         double noise_pooled, FitDiagnostics* diagnostics) {
  internal::NuisanceModel model;
  model.phase_degree = options.phase_degree;
  model.omega_prior_weight.assign(runs.size(), 0.0);
  if (options.omega_uncertainty && noise_pooled > 0.0) {
    for (std::size_t r = 0; r < runs.size(); ++r) {
      const double sd = runs.Info(r).omega_std_rad_s;
      if (std::isfinite(sd) && sd > 0.0) {
        model.omega_prior_weight[r] = noise_pooled * noise_pooled / (sd * sd);
        diagnostics->omega_nuisance = true;
      }
    }
  }
  return model;
}

// The fit on the runs as they are used: all the samples, or without the outliers once some were
// removed.
struct CleanedFit {
  FitState state;
  bool samples_removed = false;  // `cleaned` holds the runs in use (else the caller's runs)
  std::unique_ptr<internal::CleanedRuns> cleaned;
  std::vector<std::size_t> removed;     // per run: samples removed as outliers
  std::vector<double> largest_removed;  // per run: the largest in robust sigma (NaN: none)
  // The latest fit's residual statistics, one per run. The residuals themselves are not kept: a
  // run's residual matrix (32 bytes per sample) lives only while that run is examined, so the fit
  // holds the data plus one run's residuals per thread, not a second copy of the session's size
  // (docs/estimator/methods.md "Memory").
  std::vector<ResidualStatistics> residual_stats;
  bool residuals_current = false;

  const RunSet& Used(const RunSet& runs) const {
    return samples_removed ? static_cast<const RunSet&>(*cleaned) : runs;
  }
};

// Run r's samples whose worst channel's residual `e` is beyond outlier_threshold_sigma robust
// sigma (`robust`, RobustSigma(e); ascending); none in noise-free data, and none where removing
// them would thin the run below what the fit needs. Updates `largest_removed` with the worst found.
std::vector<Eigen::Index> RunOutliers(const RunData& run, const Eigen::Matrix4Xd& e, double robust,
                                      const MlOptions& options, double noise_sigma,
                                      double* largest_removed) {
  std::vector<Eigen::Index> out;
  // Noise-free data (a simulation) have rounding for residuals: nothing there is an outlier.
  const double signal_rms =
      std::sqrt(run.y.squaredNorm() / (4.0 * static_cast<double>(run.size())));
  if (!(noise_sigma > 1e-10 * signal_rms)) return out;
  const double limit = options.outlier_threshold_sigma * robust;
  for (Eigen::Index k = 0; k < e.cols(); ++k) {
    const double worst = e.col(k).cwiseAbs().maxCoeff();
    if (worst > limit) {
      out.push_back(k);
      const double in_sigma = worst / robust;
      if (!(in_sigma <= *largest_removed)) *largest_removed = in_sigma;
    }
  }
  // Never thin a run below what the fit needs.
  if (run.size() - static_cast<Eigen::Index>(out.size()) <
      std::max<Eigen::Index>(kMlMinimumSamples, run.size() / 2))
    out.clear();
  return out;
}

// One pass over the latest fit's residuals, run by run in parallel, each run's residuals made and
// dropped in turn: every run's statistics for the diagnostics (AnalyseResiduals), its outliers
// when `outliers` is given, and the fit's cost at its final point when no linearisation evaluated
// it (FitState::ne_one_step_behind). The same arithmetic as on kept residuals, so the same bits.
void ExamineResiduals(const RunSet& runs_now, const MlOptions& options,
                      const internal::NuisanceModel& model, const WhitenessNull& whiteness_null,
                      const std::vector<double>& noise_sigma,
                      std::vector<std::vector<Eigen::Index>>* outliers, CleanedFit* fit) {
  FitState& state = fit->state;
  const internal::OutputErrorProblem problem(runs_now, state.indices, options.num_threads,
                                             options.min_samples_for_threads, model);
  fit->residual_stats.assign(runs_now.size(), ResidualStatistics());
  std::vector<double> run_cost(runs_now.size(), 0.0);
  if (outliers != nullptr) outliers->assign(runs_now.size(), {});
  internal::ParallelFor(runs_now.size(), problem.Threads(), [&](std::size_t r) {
    // Held while the problem makes its residuals: a spool then hands the problem this one.
    const RunPtr run = runs_now.Load(r);
    Eigen::Matrix4Xd e;
    problem.RunResiduals(r, state.p, state.nuisance[r], &e);
    run_cost[r] = e.squaredNorm();
    fit->residual_stats[r] = AnalyseResiduals(e, whiteness_null);
    if (outliers != nullptr)
      (*outliers)[r] = RunOutliers(*run, e, fit->residual_stats[r].robust_sigma, options,
                                   noise_sigma[r], &fit->largest_removed[r]);
  });
  fit->residuals_current = true;
  if (state.ne_one_step_behind) {
    // The fit's cost at its final point, which no linearisation evaluated (FitState).
    internal::NormalEquations& ne = state.ne;
    ne.cost = 0.0;
    for (std::size_t r = 0; r < runs_now.size(); ++r) {
      ne.cost_per_run[r] = run_cost[r];
      ne.cost += ne.cost_per_run[r];
      if (model.OmegaFree(r)) {
        const double offset = state.nuisance[r][model.OmegaIndex()];
        ne.cost += model.omega_prior_weight[r] * offset * offset;
      }
    }
    state.ne_one_step_behind = false;
  }
}

// Steps 1–3 of the header, then outliers removed and the fit repeated from where it ended, until
// none is found or max_outlier_passes. False (`s` says why) when no estimate could be made.
// `noise_sigma`: a run's entry becomes NaN when its samples change.
bool FitWithoutOutliers(const RunSet& runs, const MlOptions& options,
                        const internal::NuisanceModel& model, const WhitenessNull& whiteness_null,
                        std::vector<double>* noise_sigma, FreeSet* free, CleanedFit* fit,
                        EstimateSummary* s) {
  fit->removed.assign(runs.size(), 0);
  fit->largest_removed.assign(runs.size(), kNaN);
  FitState& state = fit->state;
  const std::vector<std::string> prepared_warnings = s->warnings;
  for (int pass = 0;; ++pass) {
    const RunSet& in_use = fit->Used(runs);
    s->warnings = prepared_warnings;
    FreeSet free_pass = *free;
    const FullParameters previous = state.p;
    const std::vector<internal::RunNuisance> previous_nuisance = state.nuisance;
    fit->residuals_current = false;
    if (!Fit(in_use, options, model, pass == 0 ? nullptr : &previous,
             pass == 0 || !options.common_phase_start_from_data ? nullptr : &previous_nuisance,
             &free_pass, &state, s))
      return false;
    *free = free_pass;
    if (pass >= options.max_outlier_passes || !(options.outlier_threshold_sigma > 0.0)) break;
    std::vector<std::vector<Eigen::Index>> out;
    ExamineResiduals(in_use, options, model, whiteness_null, *noise_sigma, &out, fit);
    bool any = false;
    for (const auto& o : out) any = any || !o.empty();
    if (!any) break;
    if (!fit->cleaned) fit->cleaned = std::make_unique<internal::CleanedRuns>(runs);
    for (std::size_t r = 0; r < in_use.size(); ++r) {
      if (out[r].empty()) continue;
      fit->removed[r] += out[r].size();
      (*noise_sigma)[r] = kNaN;  // the data changed: computed again for the diagnostics
      fit->cleaned->Remove(r, out[r]);
    }
    fit->samples_removed = true;
  }
  return true;
}

// Step 4's per-run results: each run's initial state and nuisance, and its residual RMS.
void FillRunResults(const RunSet& used, const internal::NuisanceModel& model, const FitState& state,
                    EstimateSummary* s) {
  const FullParameters& p = state.p;
  for (std::size_t r = 0; r < used.size(); ++r) {
    const internal::RunNuisance& n = state.nuisance[r];
    s->initial_states.push_back(internal::TrueInitialState(p, n.head<4>()));
    RunNuisanceEstimate estimate;
    estimate.run_id = used.Info(r).id;
    estimate.initial_state = s->initial_states.back();
    for (int j = 1; j <= model.phase_degree; ++j)
      estimate.phase_coefficients.push_back(n[internal::NuisanceModel::PhaseIndex(j)]);
    if (model.OmegaFree(r)) estimate.omega_offset_rad_s = n[model.OmegaIndex()];
    s->run_nuisance.push_back(std::move(estimate));
  }
  s->residual_rms_per_run.resize(used.size());
  for (std::size_t r = 0; r < used.size(); ++r)
    s->residual_rms_per_run[r] =
        std::sqrt(state.ne.cost_per_run[r] / (4.0 * static_cast<double>(used.Info(r).samples)));
}

// The information about δ and ξ at the fit, with the runs' nuisance eliminated.
struct FitInformation {
  double s2 = kNaN;  // σ̂², the cost per degree of freedom
  bool have_information = false;
  Eigen::MatrixXd h_reduced;  // H_red
  bool have_inverse = false;
  Eigen::MatrixXd h_reduced_inverse;
};

// The recorded Ω of run r against what the data alone say (RunFitDiagnostics::omega_offset_*).
// `noise_correlation` (≥ 1): how much less the data know than the white-noise information says,
// the run's integrated noise correlation in samples when the noise is coloured (an Ω offset is a
// slow drift of the pattern: its information is the noise spectrum's at low frequency, the white
// level times that factor).
void DiagnoseOmegaOffset(std::size_t r, const internal::RunNuisance& n,
                         const internal::NuisanceModel& model, const internal::NormalEquations& ne,
                         const FitInformation& info, double noise_correlation,
                         RunFitDiagnostics* d) {
  // The fitted offset is a compromise between the prior (variance v_p = σ̂²/w) and the data
  // (variance v_d); the data's own offset is m = offset·(1/v_p + 1/v_d)·v_d, and under "the
  // recorded Ω is right within its std" m ~ N(0, v_p + v_d). v_d comes from the posterior variance
  // of the offset, 1/v_post = 1/v_p + 1/v_d, the (o, o) entry of σ̂²·H⁻¹ (Schur complement).
  const double s2 = info.s2;
  const int o = model.OmegaIndex();
  d->omega_offset_rad_s = n[o];
  const double v_p = s2 / model.omega_prior_weight[r];
  Eigen::MatrixXd h_xx_inverse;
  double v_d = kNaN;
  if (internal::InvertScaledSpd(ne.h_xx[r], &h_xx_inverse)) {
    const Eigen::VectorXd column = h_xx_inverse.col(o);
    double h_oo = column[o];
    if (info.have_inverse) {
      const Eigen::VectorXd a = ne.h_px[r] * column;
      h_oo += a.dot(info.h_reduced_inverse * a);
    }
    const double information_data = 1.0 / (s2 * h_oo) - 1.0 / v_p;
    if (information_data > 0.0) v_d = 1.0 / information_data;
  }
  if (std::isfinite(v_d)) {
    // The fit weighed prior and data as if the noise were white: that is how its offset is
    // undone into the data's own; the data's own then scatters as coloured noise makes it.
    d->omega_offset_data_rad_s = d->omega_offset_rad_s * (1.0 / v_p + 1.0 / v_d) * v_d;
    d->omega_offset_in_std =
        d->omega_offset_data_rad_s / std::sqrt(v_p + std::max(1.0, noise_correlation) * v_d);
  } else {
    d->omega_offset_in_std = d->omega_offset_rad_s / std::sqrt(v_p);
  }
}

// What the noise of the data and the fit's nuisance say about the runs, as the diagnostics carry
// them: the residuals against the model-free noise, whiteness, outliers, the common phase and Ω.
struct RunEvidence {
  const ResidualStatistics* stats = nullptr;
  double noise_sigma = kNaN;
  std::size_t outliers_removed = 0;
  double largest_outlier_in_sigma = kNaN;
};

RunFitDiagnostics DiagnoseRun(std::size_t r, const RunData& run, const RunEvidence& evidence,
                              const FitState& state, const internal::NuisanceModel& model,
                              const MlOptions& options,
                              const DifferenceNoiseModel& difference_noise,
                              const FitInformation& info) {
  const ResidualStatistics& stats = *evidence.stats;
  RunFitDiagnostics d;
  d.run_id = run.id;
  d.samples = static_cast<std::size_t>(run.size());
  d.noise_sigma = evidence.noise_sigma;
  d.residual_rms = stats.rms;
  // Noise-free data (simulation): the noise is rounding, its whiteness means nothing, and the
  // ratio is taken against a floor of 1e-10 of the signal.
  const double signal_rms = std::sqrt(run.y.squaredNorm() / (4.0 * static_cast<double>(d.samples)));
  d.noise_free = !(d.noise_sigma > 1e-10 * signal_rms);
  d.residual_ratio = stats.rms / std::max(d.noise_sigma, 1e-10 * signal_rms);
  d.residual_ratio_threshold = ResidualRatioThreshold(options.fit_quality, d.samples,
                                                      difference_noise.ratio_standard_error_scale);
  d.lag1_autocorrelation = stats.lag1_autocorrelation;
  d.whiteness_lags = stats.lags;
  d.whiteness_q = stats.ljung_box_q;
  d.whiteness_z = d.noise_free ? kNaN : stats.ljung_box_z;
  d.max_abs_residual_in_sigma = stats.max_abs_in_sigma;
  d.excess_kurtosis = stats.excess_kurtosis;
  d.outliers_removed = evidence.outliers_removed;
  d.largest_outlier_in_sigma = evidence.largest_outlier_in_sigma;
  const internal::RunNuisance& n = state.nuisance[r];
  if (model.phase_degree >= 1) d.common_frequency_rad_s = n[internal::NuisanceModel::PhaseIndex(1)];
  if (model.phase_degree >= 2)
    d.common_frequency_drift_rad_s2 = 2.0 * n[internal::NuisanceModel::PhaseIndex(2)];
  // Coloured noise (declared, or a sandwich asked for): the Ω offset's data std is the white one
  // times √(integrated correlation), as the parameters' std are the sandwich's. Without it the
  // carrier station's output filter made the check's statistic about 1.6 times too wide (RMS
  // 1.58 over good units' runs) and flagged good carrier units' fits as outside the model
  // (docs/measurements/2026-11-27-adaptive-sessions.md).
  const bool coloured_covariance =
      options.covariance == MlOptions::Covariance::kSandwich ||
      (options.covariance == MlOptions::Covariance::kAuto && !options.noise_shape.IsWhite());
  const double noise_correlation =
      coloured_covariance && std::isfinite(stats.integrated_correlation_samples)
          ? stats.integrated_correlation_samples
          : 1.0;
  if (model.OmegaFree(r)) DiagnoseOmegaOffset(r, n, model, state.ne, info, noise_correlation, &d);
  return d;
}

// Step 5's judgement of one run: a problem per check the run fails (residual ratio, whiteness,
// Ω offset), a warning for the outliers removed. True when its residuals are coloured beyond what
// the station declares.
bool JudgeRunFit(const RunFitDiagnostics& d, const MlOptions& options, bool declared_colour,
                 const WhitenessNull& whiteness_null, FitDiagnostics* diagnostics,
                 std::vector<std::string>* warnings) {
  bool coloured = false;
  const FitQualityLimits& q = options.fit_quality;
  const double id = static_cast<double>(d.run_id);
  if (!(d.residual_ratio <= d.residual_ratio_threshold))
    diagnostics->problems.push_back(Format(
        "run %.0f: residual RMS %.4g times the noise of the data (%.3g, from 4th differences; "
        "limit %.4g): the model misses something (a frequency drift, a wrong rate, noise "
        "coloured beyond what the station declares?)",
        id, d.residual_ratio, d.noise_sigma, d.residual_ratio_threshold));
  if (!d.noise_free && !(d.whiteness_z <= q.whiteness_z_max)) {
    coloured = true;
    diagnostics->problems.push_back(
        declared_colour
            ? Format("run %.0f: residuals correlated beyond the declared noise's memory "
                     "(Ljung-Box z = %.3g from lag %.0f, limit %.3g): noise coloured beyond "
                     "the declaration, or a model error",
                     id, d.whiteness_z, whiteness_null.first_lag, q.whiteness_z_max)
            : Format("run %.0f: residuals not white (Ljung-Box z = %.3g, limit %.3g; lag-1 "
                     "autocorrelation %.2f): coloured noise or a model error",
                     id, d.whiteness_z, q.whiteness_z_max, d.lag1_autocorrelation));
  }
  if (std::isfinite(d.omega_offset_in_std) &&
      !(std::abs(d.omega_offset_in_std) <= q.omega_offset_max_in_std))
    diagnostics->problems.push_back(
        Format("run %.0f: the data put its rate %.3g rad/s from the recorded one, %.3g std of "
               "the difference (limit %.3g): check the rate table's calibration",
               id, d.omega_offset_data_rad_s, d.omega_offset_in_std, q.omega_offset_max_in_std));
  if (d.outliers_removed > 0)
    warnings->push_back(
        Format("run %.0f: %.0f samples removed as outliers (beyond %.3g robust sigma; largest %.3g "
               "sigma) and the fit repeated without them",
               id, static_cast<double>(d.outliers_removed), options.outlier_threshold_sigma,
               d.largest_outlier_in_sigma));
  return coloured;
}

// The sandwich covariance H⁻¹·S·H⁻¹: S from batch sums of the reduced score, batches long against
// the residuals' correlation so that they are nearly independent. Empty when it cannot be made.
// A pass over the data.
Eigen::MatrixXd SandwichCovariance(const RunSet& used, const internal::OutputErrorProblem& problem,
                                   const FitState& state, const FitInformation& info,
                                   const std::vector<double>& integrated_correlation,
                                   const EstimateSummary& s, FitDiagnostics* diagnostics) {
  Eigen::MatrixXd sandwich;
  std::vector<Eigen::MatrixXd> projection;
  if (!info.have_inverse || !internal::NuisanceProjections(state.ne, &projection)) return sandwich;
  const Eigen::MatrixXd& h_inverse = info.h_reduced_inverse;
  const auto nf = static_cast<Eigen::Index>(state.indices.size());
  Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(nf, nf);
  std::size_t longest_batch = 0;
  std::vector<Eigen::MatrixXd> reduced(used.size());
  std::vector<std::size_t> batch(used.size());
  internal::ParallelFor(used.size(), problem.Threads(), [&](std::size_t r) {
    const auto n = static_cast<std::size_t>(used.Info(r).samples);
    const double wanted = 20.0 * integrated_correlation[r];
    batch[r] = std::clamp<std::size_t>(static_cast<std::size_t>(wanted), 16,
                                       std::max<std::size_t>(16, n / 16));
    Eigen::MatrixXd scores;
    problem.RunBlockScores(r, state.p, state.nuisance[r], batch[r], &scores);
    reduced[r] = scores.topRows(nf) - projection[r] * scores.bottomRows(scores.rows() - nf);
  });
  for (std::size_t r = 0; r < used.size(); ++r) {
    longest_batch = std::max(longest_batch, batch[r]);
    meat.noalias() += reduced[r] * reduced[r].transpose();
  }
  sandwich = h_inverse * meat * h_inverse;
  sandwich = 0.5 * (sandwich + sandwich.transpose()).eval();
  diagnostics->sandwich_batch_samples = longest_batch;
  double ratio = 0.0;
  for (Eigen::Index c = 0; c < nf; ++c)
    ratio = std::max(ratio, std::sqrt(std::max(0.0, sandwich(c, c)) / s.covariance(c, c)));
  diagnostics->sandwich_to_white_std_max = ratio;
  return sandwich;
}

// Ω taken as exact: what a 1e-6 rad/s error of each such run's Ω would do (summary.hpp). With run
// r's Ω as one more nuisance (ΔΩ last, NuisanceModel), the Gauss–Newton answer to a fixed shift ε
// of it, every other nuisance of the run re-fitted, is Δθ = −H_red⁻¹·b·ε with
// b = h_pΩ − H_px'·H_x'x'⁻¹·h_x'Ω (x' the run's other nuisance). The prior weight only enters the
// (Ω, Ω) entry, which this does not use: any positive weight gives the same b. No pass over the
// data: b comes from the Gram sums of the fit's last linearisation
// (OutputErrorProblem::InformationAt), as its covariance does.
void OmegaExactSensitivity(const RunSet& used, const internal::NuisanceModel& model,
                           const FitState& state, const MlOptions& options,
                           const FitInformation& info, EstimateSummary* s) {
  const std::vector<int>& indices = state.indices;
  std::vector<std::size_t> exact;
  for (std::size_t r = 0; r < used.size(); ++r)
    if (!model.OmegaFree(r)) exact.push_back(r);
  if (exact.empty() || !info.have_inverse) return;
  internal::NuisanceModel with_omega = model;
  for (std::size_t r : exact) with_omega.omega_prior_weight[r] = 1.0;
  // A point's nuisance with ΔΩ = 0 appended for the runs whose Ω is taken as exact.
  const auto with_offset = [&](std::vector<internal::RunNuisance> nuisance) {
    for (std::size_t r : exact) {
      nuisance[r].conservativeResize(nuisance[r].size() + 1);
      nuisance[r][nuisance[r].size() - 1] = 0.0;
    }
    return nuisance;
  };
  const internal::OutputErrorProblem omega_problem(used, indices, options.num_threads,
                                                   options.min_samples_for_threads, with_omega);
  internal::NormalEquations ne_omega;
  // The last linearisation always has its Gram sums; were they missing, a pass over the data
  // gives the same information rather than no sensitivity (and no warning) at all.
  if (state.ne.nuisance.size() != used.size() ||
      !omega_problem.InformationAt(state.ne, with_offset(state.ne.nuisance), &ne_omega))
    omega_problem.Linearize(state.p, with_offset(state.nuisance), &ne_omega);
  const int o = with_omega.OmegaIndex();
  double largest_in_std = 0.0;
  std::string run_list;
  for (std::size_t r : exact) {
    const Eigen::MatrixXd& h_xx = ne_omega.h_xx[r];
    const Eigen::MatrixXd& h_px = ne_omega.h_px[r];
    const Eigen::MatrixXd h_other = h_xx.topLeftCorner(o, o);
    Eigen::MatrixXd h_other_inverse;
    if (!internal::InvertScaledSpd(h_other, &h_other_inverse)) continue;
    // Plain matrices, not nested block expressions (which GCC 12 flags as a potential null
    // dereference inside Eigen).
    const Eigen::VectorXd h_other_omega = h_xx.col(o).head(o);
    const Eigen::VectorXd solved = h_other_inverse * h_other_omega;
    const Eigen::MatrixXd h_p_other = h_px.leftCols(o);
    const Eigen::VectorXd b = h_px.col(o) - h_p_other * solved;
    const Eigen::VectorXd change = -kOmegaSensitivityStepRadS * (info.h_reduced_inverse * b);
    OmegaSensitivity sensitivity;
    sensitivity.run_id = used.Info(r).id;
    for (std::size_t c = 0; c < indices.size(); ++c) {
      const int full = indices[c];
      const auto ci = static_cast<Eigen::Index>(c);
      if (full < internal::kXiOffset)
        sensitivity.delta[full] = change[ci];
      else
        sensitivity.xi[full - internal::kXiOffset] = change[ci];
      const double sd =
          full < internal::kXiOffset ? s->delta_std[full] : s->xi_std[full - internal::kXiOffset];
      if (sd > 0.0) largest_in_std = std::max(largest_in_std, std::abs(change[ci]) / sd);
    }
    s->omega_sensitivity.push_back(sensitivity);
    run_list += (run_list.empty() ? "" : ", ") + std::to_string(used.Info(r).id);
  }
  if (!s->omega_sensitivity.empty())
    s->warnings.push_back(
        "Omega taken as exact in run" + std::string(exact.size() > 1 ? "s " : " ") + run_list +
        " (no recorded standard error, or its use turned off): the std do not include the "
        "rates' error; a 1e-06 rad/s error of one run's Omega moves the estimate by up to " +
        Format("%.3g", largest_in_std) + " std (omega_sensitivity)");
}

// The wave precesses at −δ2·Ω relative to the case with δ2 = k > 0 for every resonator of this
// kind: a significantly negative δ2 fits data whose rates have the wrong sign (the unit's axis
// mounted the other way, the table's sign). Such data fit perfectly, so no residual check sees
// it. (Not the I/Q convention: conjugating the channels leaves δ2 as it is, iq_convention.hpp.)
void CheckAngularGainSign(const EstimateSummary& s, FitDiagnostics* diagnostics) {
  if (s.delta_estimated[1] && std::isfinite(s.delta_std[1]) &&
      s.delta[1] < -kNegativeAngularGainInStd * s.delta_std[1])
    diagnostics->problems.push_back(Format(
        "angular gain delta2 = %.6g is negative (%.3g std below 0): the wave turns with the case, "
        "not against it as every such resonator does. Likely the recorded rates have the wrong "
        "sign (the unit's sensitive axis, the table's sign convention)",
        s.delta[1], -s.delta[1] / s.delta_std[1]));
}

}  // namespace

EstimateSummary EstimateMaximumLikelihood(const std::vector<RunData>& runs,
                                          const MlOptions& options) {
  return EstimateMaximumLikelihood(RunsInMemory(runs), options);
}

EstimateSummary EstimateMaximumLikelihood(const RunSet& runs, const MlOptions& options) {
  EstimateSummary s;
  s.method = "ml";
  s.message.clear();
  FreeSet free;
  if (!Prepare(runs, options, &s, &free)) return s;
  s.samples_used = runs.TotalSamples();
  FitDiagnostics& diagnostics = s.diagnostics;
  diagnostics.limits = options.fit_quality;
  diagnostics.phase_degree = options.phase_degree;

  // The noise the data carry, from the data alone: it weighs the priors on Ω, and the residuals are
  // judged against it.
  const DifferenceNoiseModel difference_noise = DifferenceNoiseModelFor(options.noise_shape);
  const WhitenessNull whiteness_null =
      WhitenessNullFor(options.noise_shape, options.whiteness_lags);
  const bool declared_colour = !options.noise_shape.IsWhite();
  diagnostics.noise_shape = options.noise_shape.description;
  diagnostics.difference_stride = difference_noise.stride;
  diagnostics.whiteness_first_lag = whiteness_null.first_lag;
  DataNoise noise = MeasureDataNoise(runs, difference_noise, s.samples_used);
  std::vector<double>& noise_sigma = noise.sigma;
  const internal::NuisanceModel model = NuisanceModelFor(runs, options, noise.pooled, &diagnostics);

  // Fit; remove outliers; fit again from there.
  CleanedFit fit;
  if (!FitWithoutOutliers(runs, options, model, whiteness_null, &noise_sigma, &free, &fit, &s))
    return s;
  const RunSet& used = fit.Used(runs);
  if (!fit.residuals_current)
    ExamineResiduals(used, options, model, whiteness_null, noise_sigma, nullptr, &fit);
  const FitState& state = fit.state;
  const FullParameters& p = state.p;
  const internal::NormalEquations& ne = state.ne;
  const std::vector<int>& indices = state.indices;
  const internal::OutputErrorProblem problem(used, indices, options.num_threads,
                                             options.min_samples_for_threads, model);
  s.threads_used = state.threads;
  s.samples_used = used.TotalSamples();

  // 4. Results.
  FillParameters(p, free, &s);
  FillRunResults(used, model, state, &s);
  double samples_cost = 0.0;
  for (double c : ne.cost_per_run) samples_cost += c;
  s.residual_rms = std::sqrt(samples_cost / static_cast<double>(problem.NumObservations()));
  FitInformation info;
  info.s2 = ne.cost / state.dof;
  s.noise_sigma = std::sqrt(info.s2);
  info.have_information = !indices.empty() && internal::ReducedInformation(ne, &info.h_reduced);
  if (info.have_information) FillCovariance(info.h_reduced, indices, info.s2, &s);
  if (!p.allFinite()) {
    s.termination = Termination::kNumericalFailure;
    s.message = "non-finite estimate";
    return s;
  }
  if (s.termination == Termination::kMaxIterations)
    s.warnings.push_back("not converged within max_iterations; the estimate is the best found");

  // 5. Is the fit right? Per run: residuals against the model-free noise, whiteness, outliers, the
  // common phase and Ω offsets.
  std::vector<double> integrated_correlation(used.size(), 1.0);
  bool coloured = false;
  info.have_inverse =
      info.have_information && internal::InvertScaledSpd(info.h_reduced, &info.h_reduced_inverse);
  const std::vector<ResidualStatistics>& run_stats = fit.residual_stats;
  internal::ParallelFor(used.size(), problem.Threads(), [&](std::size_t r) {
    if (!std::isfinite(noise_sigma[r]))
      noise_sigma[r] = DifferenceNoiseSigma(used.Load(r)->y, difference_noise);
  });
  for (std::size_t r = 0; r < used.size(); ++r) {
    const RunEvidence evidence{&run_stats[r], noise_sigma[r], fit.removed[r],
                               fit.largest_removed[r]};
    const RunFitDiagnostics d =
        DiagnoseRun(r, *used.Load(r), evidence, state, model, options, difference_noise, info);
    integrated_correlation[r] = run_stats[r].integrated_correlation_samples;
    if (JudgeRunFit(d, options, declared_colour, whiteness_null, &diagnostics, &s.warnings))
      coloured = true;
    diagnostics.runs.push_back(d);
  }

  // The sandwich covariance, computed only when it is reported (a pass over the data).
  Eigen::MatrixXd sandwich;
  const bool sandwich_wanted =
      options.covariance == MlOptions::Covariance::kSandwich ||
      (options.covariance == MlOptions::Covariance::kAuto && (coloured || declared_colour));
  if (info.have_information && s.covariance.rows() == static_cast<Eigen::Index>(indices.size()) &&
      sandwich_wanted)
    sandwich =
        SandwichCovariance(used, problem, state, info, integrated_correlation, s, &diagnostics);
  const bool use_sandwich = sandwich.size() > 0;
  if (use_sandwich) {
    SetCovariance(sandwich, indices, &s);
    diagnostics.covariance_kind = "sandwich";
    // Colour the station declared is expected, not a warning: the record says which covariance.
    if (coloured || !declared_colour)
      s.warnings.push_back(Format(
          "residuals are not white: the std are from the sandwich covariance (batches of %.0f "
          "samples; up to %.3g times the white-noise std)",
          static_cast<double>(diagnostics.sandwich_batch_samples),
          diagnostics.sandwich_to_white_std_max));
  }
  OmegaExactSensitivity(used, model, state, options, info, &s);
  CheckAngularGainSign(s, &diagnostics);
  for (const std::string& problem_text : diagnostics.problems) s.warnings.push_back(problem_text);
  return s;
}

}  // namespace hrgbench::estimator
