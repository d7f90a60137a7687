#pragma once
// Cramér–Rao bound of a planned experiment: the smallest standard deviation any unbiased estimator
// can reach for δ and the unknown ξ, given the truth, the noise σ and the runs, with one unknown
// initial state per run as a nuisance parameter. Judges a plan before it is run.

#include <string>
#include <vector>

#include "hrgbench/estimator/identifiability.hpp"
#include "hrgbench/estimator/run_data.hpp"
#include "hrgbench/estimator/summary.hpp"

namespace hrgbench::estimator {

struct DesignSpec {
  Delta delta = Delta::Zero();
  Xi xi = Xi::Zero();
  double sigma = 1e-4;         // noise std on each channel of y
  XiMask xi_unknown = kAllXi;  // which ξ are estimated (the rest known)
  // Degree of the per-run common phase the estimator takes as unknown (MlOptions::phase_degree):
  // the bound of the estimator that does not depend on the demodulation reference's phase.
  int phase_degree = 2;
  std::vector<RunPlan> runs;

  bool IsValid(std::string* why) const;
};

struct CrlbResult {
  bool valid = false;
  std::string message = "CramerRaoBound was not called";
  Delta delta_std = Delta::Constant(kNaN);
  Xi xi_std = Xi::Constant(kNaN);  // NaN where ξ is known
  Eigen::MatrixXd covariance;      // of δ then the unknown ξ
  std::size_t samples = 0;
  IdentifiabilityReport identifiability;  // rules and numerical rank of this design
};

CrlbResult CramerRaoBound(const DesignSpec& design, const IdentifiabilityOptions& options = {});

}  // namespace hrgbench::estimator
