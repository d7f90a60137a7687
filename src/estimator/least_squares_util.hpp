#pragma once
// Small helpers shared by the estimators. Internal to the estimator library.

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

#include "hrgbench/estimator/run_data.hpp"
#include "hrgbench/estimator/run_set.hpp"

namespace hrgbench::estimator::internal {

// Solves the symmetric positive definite system H·x = b after scaling H to unit diagonal: the
// parameters differ by ten orders of magnitude in scale (δ1 ~ 1e-3 1/s against ξ ~ 1e-2, with Ω·t
// factors in between), and an unscaled Cholesky would lose those digits. False if not SPD.
template <typename MatrixType, typename VectorType>
bool SolveScaledSpd(const MatrixType& h, const VectorType& b, VectorType* x) {
  const Eigen::Index n = h.rows();
  Eigen::VectorXd d(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!(h(i, i) > 0.0) || !std::isfinite(h(i, i))) return false;
    d[i] = 1.0 / std::sqrt(h(i, i));
  }
  const Eigen::MatrixXd scaled = d.asDiagonal() * Eigen::MatrixXd(h) * d.asDiagonal();
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(scaled);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
  const Eigen::VectorXd y = ldlt.solve(Eigen::VectorXd(d.asDiagonal() * b));
  const Eigen::VectorXd solution = d.asDiagonal() * y;
  if (!solution.allFinite()) return false;
  *x = solution;
  return true;
}

template <typename MatrixType>
bool InvertScaledSpd(const MatrixType& h, MatrixType* inverse) {
  const Eigen::Index n = h.rows();
  Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(n, n);
  Eigen::VectorXd d(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!(h(i, i) > 0.0) || !std::isfinite(h(i, i))) return false;
    d[i] = 1.0 / std::sqrt(h(i, i));
  }
  const Eigen::MatrixXd scaled = d.asDiagonal() * Eigen::MatrixXd(h) * d.asDiagonal();
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(scaled);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
  const Eigen::MatrixXd result = d.asDiagonal() * ldlt.solve(identity) * d.asDiagonal();
  if (!result.allFinite()) return false;
  *inverse = result;
  return true;
}

inline std::size_t CountSamples(const std::vector<RunData>& runs) {
  std::size_t n = 0;
  for (const RunData& r : runs) n += static_cast<std::size_t>(r.size());
  return n;
}

// Checks what every estimator needs of a run: matching sizes, at least `min_samples`, strictly
// increasing finite time, finite y (not all zero) and Ω. `r`: its place (0-based), which names it
// when it has no id.
inline bool ValidateRun(const RunData& run, std::size_t r, std::size_t min_samples,
                        std::string* why) {
  const std::string name = "run " + std::to_string(run.id != 0 ? run.id : static_cast<int>(r + 1));
  if (static_cast<Eigen::Index>(run.t_s.size()) != run.y.cols()) {
    *why = name + ": " + std::to_string(run.t_s.size()) + " time stamps but " +
           std::to_string(run.y.cols()) + " samples";
    return false;
  }
  if (run.t_s.size() < min_samples) {
    *why = name + ": " + std::to_string(run.t_s.size()) + " samples, the method needs at least " +
           std::to_string(min_samples);
    return false;
  }
  if (!std::isfinite(run.omega_rad_s)) {
    *why = name + ": omega_rad_s is not finite";
    return false;
  }
  // One pass over the samples for all three checks below, which are reported in this order.
  bool y_finite = true, y_nonzero = false;
  std::size_t bad_time = run.t_s.size();  // the first sample where t_s is not finite or increasing
  const double* y = run.y.data();
  for (std::size_t k = 0; k < run.t_s.size(); ++k) {
    const double a = y[4 * k], b = y[4 * k + 1], c = y[4 * k + 2], d = y[4 * k + 3];
    y_finite =
        y_finite && std::isfinite(a) && std::isfinite(b) && std::isfinite(c) && std::isfinite(d);
    y_nonzero = y_nonzero || a != 0.0 || b != 0.0 || c != 0.0 || d != 0.0;
    if (bad_time == run.t_s.size() &&
        (!std::isfinite(run.t_s[k]) || (k > 0 && !(run.t_s[k] > run.t_s[k - 1]))))
      bad_time = k;
  }
  if (!y_finite) {
    *why = name + ": y holds a non-finite value";
    return false;
  }
  // All zero carries neither a wave nor noise: every ratio of the fit would be 0/0 and its
  // messages "-nan"; say what the data are instead.
  if (run.y.size() > 0 && !y_nonzero) {
    *why = name +
           ": y is all zero (no wave and no noise on any channel): nothing to fit; is "
           "the pick-off or its electronics connected?";
    return false;
  }
  if (bad_time < run.t_s.size()) {
    *why =
        name + ": t_s is not finite and strictly increasing at sample " + std::to_string(bad_time);
    return false;
  }
  return true;
}

// ... and that there is at least one run.
inline bool ValidateRunData(const std::vector<RunData>& runs, std::size_t min_samples,
                            std::string* why) {
  if (runs.empty()) {
    *why = "no runs to estimate from";
    return false;
  }
  for (std::size_t r = 0; r < runs.size(); ++r)
    if (!ValidateRun(runs[r], r, min_samples, why)) return false;
  return true;
}

// The same over a set read run by run: one pass over its samples.
inline bool ValidateRunData(const RunSet& runs, std::size_t min_samples, std::string* why) {
  if (runs.size() == 0) {
    *why = "no runs to estimate from";
    return false;
  }
  for (std::size_t r = 0; r < runs.size(); ++r)
    if (!ValidateRun(*runs.Load(r), r, min_samples, why)) return false;
  return true;
}

}  // namespace hrgbench::estimator::internal
