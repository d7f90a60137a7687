#include "hrgbench/estimator/paper_method.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <cstdio>

#include "hrgbench/estimator/model.hpp"
#include "least_squares_util.hpp"

namespace hrgbench::estimator {
namespace {

// One equation of the paper's method: at the centre of each derivative window, the line-fit slope
// of r and the line-fit value of r (the window mean, which is the fit's value at the mean time).
struct WindowEquations {
  std::vector<double> omega_rad_s;           // per equation
  std::vector<Forms> r_centre;               // regressor point
  std::vector<Forms> dr_dt;                  // numerical derivative
  std::vector<std::size_t> run_of_equation;  // index into runs
};

WindowEquations BuildWindowEquations(const std::vector<RunData>& runs, int window) {
  WindowEquations eq;
  const auto n_window = static_cast<std::size_t>(window);
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const RunData& run = runs[r];
    const auto n = static_cast<std::size_t>(run.size());
    std::vector<Forms> forms(n);
    for (std::size_t k = 0; k < n; ++k)
      forms[k] = QuadraticForms(run.y.col(static_cast<Eigen::Index>(k)));
    for (std::size_t start = 0; start + n_window <= n; ++start) {
      double t_mean = 0.0;
      Forms z_mean = Forms::Zero();
      for (std::size_t k = start; k < start + n_window; ++k) {
        t_mean += run.t_s[k];
        z_mean += forms[k];
      }
      t_mean /= static_cast<double>(n_window);
      z_mean /= static_cast<double>(n_window);
      double stt = 0.0;
      Forms stz = Forms::Zero();
      for (std::size_t k = start; k < start + n_window; ++k) {
        const double dt = run.t_s[k] - t_mean;
        stt += dt * dt;
        stz += dt * (forms[k] - z_mean);
      }
      eq.omega_rad_s.push_back(run.omega_rad_s);
      eq.r_centre.push_back(z_mean);
      eq.dr_dt.push_back(stz / stt);
      eq.run_of_equation.push_back(r);
    }
  }
  return eq;
}

// OLS of dr/dt on 2·regressor·δ; returns false when singular. `sse` gets the residual sum of
// squares, `per_run_sse`/`per_run_count` its split by run.
template <typename RegressorFn>
bool SolveOls(const WindowEquations& eq, std::size_t n_runs, RegressorFn regressor, Delta* delta,
              double* sse, Eigen::Matrix<double, 6, 6>* normal_out,
              std::vector<double>* per_run_sse) {
  Eigen::Matrix<double, 6, 6> normal = Eigen::Matrix<double, 6, 6>::Zero();
  Delta rhs = Delta::Zero();
  for (std::size_t i = 0; i < eq.r_centre.size(); ++i) {
    const Matrix46 m = 2.0 * regressor(eq.omega_rad_s[i], eq.r_centre[i]);
    normal.noalias() += m.transpose() * m;
    rhs.noalias() += m.transpose() * eq.dr_dt[i];
  }
  Delta solution = Delta::Zero();
  if (!internal::SolveScaledSpd(normal, rhs, &solution)) return false;
  *delta = solution;
  if (normal_out) *normal_out = normal;
  // The residual is summed directly, not as yᵀy − δᵀMᵀy: near the optimum the two terms agree to
  // more digits than a double holds, and the grid search compares exactly these small numbers.
  if (per_run_sse) per_run_sse->assign(n_runs, 0.0);
  double total = 0.0;
  for (std::size_t i = 0; i < eq.r_centre.size(); ++i) {
    const double e =
        (eq.dr_dt[i] - 2.0 * regressor(eq.omega_rad_s[i], eq.r_centre[i]) * solution).squaredNorm();
    if (per_run_sse) (*per_run_sse)[eq.run_of_equation[i]] += e;
    total += e;
  }
  *sse = total;
  return true;
}

EstimateSummary Begin(const char* method) {
  EstimateSummary s;
  s.method = method;
  s.message.clear();
  return s;
}

bool ValidateRuns(const std::vector<RunData>& runs, const PaperOptions& options,
                  EstimateSummary* s) {
  std::string why;
  if (!options.IsValid(&why) ||
      !internal::ValidateRunData(runs, static_cast<std::size_t>(PaperMinimumSamples(options)),
                                 &why)) {
    s->termination = Termination::kInvalidInput;
    s->message = why;
    return false;
  }
  return true;
}

void Finish(const WindowEquations& eq, std::size_t n_runs,
            const Eigen::Matrix<double, 6, 6>& normal, const std::vector<double>& per_run_sse,
            double sse, EstimateSummary* s) {
  const std::size_t n_obs = 4 * eq.r_centre.size();
  std::vector<std::size_t> per_run_count(n_runs, 0);
  for (std::size_t r : eq.run_of_equation) per_run_count[r] += 4;
  s->residual_rms_per_run.resize(n_runs);
  for (std::size_t r = 0; r < n_runs; ++r)
    s->residual_rms_per_run[r] =
        per_run_count[r] ? std::sqrt(per_run_sse[r] / static_cast<double>(per_run_count[r])) : kNaN;
  s->residual_rms = std::sqrt(sse / static_cast<double>(n_obs));
  // Textbook OLS covariance. The windows overlap, so the equation errors are strongly correlated
  // and this std is optimistic: it is reported for comparison only.
  const double dof = static_cast<double>(n_obs) - 6.0;
  const double s2 = dof > 0 ? sse / dof : kNaN;
  s->noise_sigma = kNaN;
  Eigen::Matrix<double, 6, 6> cov;
  if (internal::InvertScaledSpd(normal, &cov)) {
    s->covariance = s2 * cov;
    for (int j = 0; j < 6; ++j) s->delta_std[j] = std::sqrt(std::max(0.0, s->covariance(j, j)));
  }
  s->warnings.push_back(
      "equation-error std from overlapping derivative windows: optimistic, for comparison only");
}

}  // namespace

bool PaperOptions::IsValid(std::string* why) const {
  if (derivative_window < 3) {
    if (why) *why = "derivative_window must be >= 3, got " + std::to_string(derivative_window);
    return false;
  }
  if (!(xi1_step > 0.0) || !(xi1_max >= xi1_min) || !std::isfinite(xi1_min) ||
      !std::isfinite(xi1_max) || (xi1_max - xi1_min) / xi1_step > 1e8) {
    if (why) *why = "xi1 grid needs finite xi1_min <= xi1_max and 0 < step, at most 1e8 points";
    return false;
  }
  return true;
}

int PaperMinimumSamples(const PaperOptions& options) { return options.derivative_window; }

EstimateSummary EstimatePaper(const std::vector<RunData>& runs, const PaperOptions& options) {
  EstimateSummary s = Begin("paper");
  if (!ValidateRuns(runs, options, &s)) return s;
  const WindowEquations eq = BuildWindowEquations(runs, options.derivative_window);
  Delta delta = Delta::Zero();
  double sse = 0.0;
  Eigen::Matrix<double, 6, 6> normal;
  std::vector<double> per_run_sse;
  if (!SolveOls(eq, runs.size(), FormsRegressor, &delta, &sse, &normal, &per_run_sse)) {
    s.termination = Termination::kNumericalFailure;
    s.message = "the regression matrix is singular: the runs do not excite every parameter";
    return s;
  }
  s.delta = delta;
  s.delta_estimated.fill(true);
  s.xi = Xi::Zero();
  s.xi_std = Xi::Constant(kNaN);
  s.samples_used = internal::CountSamples(runs);
  s.iterations = 1;
  s.termination = Termination::kConverged;
  s.message = "OLS on line-fit derivatives, xi ignored";
  Finish(eq, runs.size(), normal, per_run_sse, sse, &s);
  return s;
}

EstimateSummary EstimatePaperXiGrid(const std::vector<RunData>& runs, const PaperOptions& options) {
  EstimateSummary s = Begin("paper-xi-grid");
  if (!ValidateRuns(runs, options, &s)) return s;
  const WindowEquations eq = BuildWindowEquations(runs, options.derivative_window);
  const auto points =
      static_cast<long>(std::floor((options.xi1_max - options.xi1_min) / options.xi1_step + 1e-9)) +
      1;
  double best_sse = std::numeric_limits<double>::infinity();
  double best_xi1 = kNaN;
  Delta best_delta = Delta::Constant(kNaN);
  // As the paper describes: at every grid point the regression is rebuilt and δ re-solved.
  for (long i = 0; i < points; ++i) {
    const double lambda = options.xi1_min + static_cast<double>(i) * options.xi1_step;
    const auto regressor = [lambda](double omega, const Forms& r) {
      return FirstOrderFormsRegressor(omega, r, lambda, 0.0);
    };
    Delta delta = Delta::Zero();
    double sse = 0.0;
    if (!SolveOls(eq, runs.size(), regressor, &delta, &sse, nullptr, nullptr)) continue;
    if (sse < best_sse) {
      best_sse = sse;
      best_xi1 = lambda;
      best_delta = delta;
    }
  }
  if (!std::isfinite(best_sse)) {
    s.termination = Termination::kNumericalFailure;
    s.message = "the regression matrix is singular at every grid point";
    return s;
  }
  const auto regressor = [best_xi1](double omega, const Forms& r) {
    return FirstOrderFormsRegressor(omega, r, best_xi1, 0.0);
  };
  Delta delta = Delta::Zero();
  double sse = 0.0;
  Eigen::Matrix<double, 6, 6> normal;
  std::vector<double> per_run_sse;
  SolveOls(eq, runs.size(), regressor, &delta, &sse, &normal, &per_run_sse);
  s.delta = delta;
  s.delta_estimated.fill(true);
  s.xi = Xi(best_xi1, 0.0, 0.0, 0.0);
  s.xi_estimated = kXi1Only;
  s.xi_std = Xi::Constant(kNaN);
  s.samples_used = internal::CountSamples(runs);
  s.iterations = static_cast<int>(points);
  s.termination = Termination::kConverged;
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, "xi1 grid of %ld points, step %.3g on [%.3g, %.3g]", points,
                options.xi1_step, options.xi1_min, options.xi1_max);
  s.message = buffer;
  Finish(eq, runs.size(), normal, per_run_sse, sse, &s);
  if (best_xi1 <= options.xi1_min || best_xi1 >= options.xi1_max)
    s.warnings.push_back("xi1 is at the edge of the grid: the true value may lie outside");
  s.warnings.push_back("xi1 from a grid has no std (the paper gives none)");
  return s;
}

}  // namespace hrgbench::estimator
