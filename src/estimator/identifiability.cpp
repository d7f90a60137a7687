#include "hrgbench/estimator/identifiability.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace hrgbench::estimator {

bool IdentifiabilityOptions::IsValid(std::string* why) const {
  if (!(distinct_omega_tol_rad_s >= 0.0)) {
    if (why) *why = "distinct_omega_tol_rad_s must be >= 0";
    return false;
  }
  if (!(max_condition > 1.0)) {
    if (why) *why = "max_condition must be > 1";
    return false;
  }
  return true;
}

bool IdentifiabilityReport::AllIdentifiable(const XiMask& requested) const {
  for (bool b : delta_identifiable)
    if (!b) return false;
  for (int k = 0; k < 4; ++k)
    if (requested[k] && !xi_identifiable[k]) return false;
  return true;
}

XiMask IdentifiabilityReport::IdentifiableXi(const XiMask& requested) const {
  XiMask out = kNoXi;
  for (int k = 0; k < 4; ++k) out[k] = requested[k] && xi_identifiable[k];
  return out;
}

IdentifiabilityReport CheckRatePlan(const std::vector<double>& omegas, const XiMask& requested,
                                    const IdentifiabilityOptions& options) {
  IdentifiabilityReport report;
  std::vector<double> sorted = omegas;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    if (i == 0 || sorted[i] - sorted[i - 1] > options.distinct_omega_tol_rad_s)
      ++report.distinct_omegas;
    if (std::abs(sorted[i]) > options.distinct_omega_tol_rad_s) report.has_nonzero_omega = true;
  }
  if (omegas.empty()) {
    report.delta_identifiable.fill(false);
    report.xi_identifiable = kNoXi;
    report.reasons.push_back("the plan has no runs");
    return report;
  }
  if (!report.has_nonzero_omega) {
    report.delta_identifiable[kScaleFactor] = false;
    report.reasons.push_back(
        "every run is at Ω = 0: the angular gain δ2 enters only through 2Ωδ2 and cannot be "
        "determined; it is held at its given value");
  }
  const bool any_xi = std::any_of(requested.begin(), requested.end(), [](bool b) { return b; });
  if (any_xi && (report.distinct_omegas < 2 || !report.has_nonzero_omega)) {
    report.xi_identifiable = kNoXi;
    report.reasons.push_back(
        report.distinct_omegas < 2
            ? "all runs share one Ω: the pick-off errors ξ look exactly like the anisotropies "
              "δ3…δ6 and cannot be separated; ξ is held at its given value (runs at two or more "
              "distinct Ω are needed)"
            : "no run has Ω ≠ 0: ξ acts through 4Ωδ2ξ and cannot be determined; ξ is held at its "
              "given value");
  }
  return report;
}

double CheckInformation(const Eigen::MatrixXd& information, const std::array<bool, 6>& delta_free,
                        const XiMask& xi_free, const IdentifiabilityOptions& options,
                        IdentifiabilityReport* report) {
  // Parameter k of `information` is the k-th free one in δ-then-ξ order.
  std::vector<int> names;  // 0..5 δ, 6..9 ξ
  for (int j = 0; j < 6; ++j)
    if (delta_free[j]) names.push_back(j);
  for (int k = 0; k < 4; ++k)
    if (xi_free[k]) names.push_back(6 + k);
  std::vector<int> active(names.size());
  for (std::size_t i = 0; i < active.size(); ++i) active[i] = static_cast<int>(i);

  double condition = 1.0;
  while (!active.empty()) {
    const auto n = static_cast<Eigen::Index>(active.size());
    Eigen::MatrixXd scaled(n, n);
    Eigen::VectorXd scale(n);
    bool zero_diagonal = false;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double d = information(active[i], active[i]);
      scale[i] = d > 0.0 ? 1.0 / std::sqrt(d) : 0.0;
      zero_diagonal = zero_diagonal || !(d > 0.0);
    }
    Eigen::Index worst = -1;
    if (zero_diagonal) {
      for (Eigen::Index i = 0; i < n && worst < 0; ++i)
        if (!(information(active[i], active[i]) > 0.0)) worst = i;
      condition = std::numeric_limits<double>::infinity();
    } else {
      for (Eigen::Index i = 0; i < n; ++i)
        for (Eigen::Index j = 0; j < n; ++j)
          scaled(i, j) = information(active[i], active[j]) * scale[i] * scale[j];
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(scaled);
      const Eigen::VectorXd& values = eig.eigenvalues();  // ascending
      condition =
          values[0] > 0.0 ? values[n - 1] / values[0] : std::numeric_limits<double>::infinity();
      if (condition <= options.max_condition) break;
      // The parameter with the largest share of the nearly null direction goes first.
      eig.eigenvectors().col(0).cwiseAbs().maxCoeff(&worst);
    }
    const int name = names[static_cast<std::size_t>(active[worst])];
    char buffer[200];
    std::snprintf(buffer, sizeof buffer,
                  "%s is not determined by this plan (scaled information condition %.2g > %.2g); "
                  "it is held at its given value",
                  name < 6 ? kDeltaNames[name].data() : kXiNames[name - 6].data(), condition,
                  options.max_condition);
    report->reasons.emplace_back(buffer);
    if (name < 6)
      report->delta_identifiable[name] = false;
    else
      report->xi_identifiable[name - 6] = false;
    active.erase(active.begin() + worst);
  }
  report->condition_number = active.empty() ? kNaN : condition;
  return report->condition_number;
}

}  // namespace hrgbench::estimator
