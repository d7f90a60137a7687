#pragma once
// The output-error least-squares problem shared by maximum likelihood and the Cramér–Rao bound:
//   residual_k = y_k − G·exp(A(Ω_r, δ)·t_k)·G⁻¹·w0_r   for every sample k of every run r,
// G = I + C(ξ), with parameters p = (δ1…δ6, ξ1…ξ4), of which a chosen subset is free, and one
// observed initial state w0 = G·x(0) per run.
//
// Why w0 and not x(0): at small Ω, G nearly commutes with exp(A·t), so a change of ξ is almost
// entirely absorbed by a change of x(0) — a large, bilinear coupling around a tiny identifiable
// effect (~4Ωδ2·t·Δξ). With x(0) as the nuisance, Gauss–Newton sees that cancellation only to first
// order and crawls (linear convergence, dozens of iterations on the paper's design); with w0 held,
// the cancellation is exact and convergence is quadratic. The reduced information of (δ, ξ) — and
// so the covariance and the CRLB — is the same in both parameterisations.
//
// Linearize() accumulates the normal equations JᵀJ, Jᵀr in the block structure the problem has (the
// x0 of one run touches only that run's samples), so the per-run blocks can be eliminated by a Schur
// complement: the cost is linear in the number of samples, and the linear algebra is at most 10×10.
// The sample loop works on buffers sized before it starts; it does not allocate.
//
// Internal to the estimator library.

#include <vector>

#include <Eigen/Core>

#include "hrgbench/estimator/parameters.hpp"
#include "hrgbench/estimator/run_data.hpp"

namespace hrgbench::estimator::internal {

using FullParameters = Eigen::Matrix<double, 10, 1>;  // (δ1…δ6, ξ1…ξ4)
inline constexpr int kXiOffset = 6;

FullParameters Pack(const Delta& delta, const Xi& xi);

struct NormalEquations {
  Eigen::MatrixXd h_pp;                                       // free × free
  Eigen::VectorXd g_p;                                        // Jᵀ·residual, free part
  std::vector<Eigen::Matrix<double, Eigen::Dynamic, 4>> h_px;  // per run, free × 4
  std::vector<Eigen::Matrix4d> h_xx;                          // per run
  std::vector<Eigen::Vector4d> g_x;                           // per run
  double cost = 0.0;                                          // Σ residual²
  std::vector<double> cost_per_run;
};

class OutputErrorProblem {
 public:
  // `free` lists the estimated entries of FullParameters, ascending. `runs` must outlive this.
  // `threads`: 0 = all hardware threads, 1 = none created; runs are spread over them, and only
  // when the runs hold at least `min_samples_for_threads` samples (MlOptions says why).
  OutputErrorProblem(const std::vector<RunData>& runs, std::vector<int> free, int threads = 1,
                     std::size_t min_samples_for_threads = 0);

  int NumFree() const { return static_cast<int>(free_.size()); }
  int Threads() const { return threads_; }
  const std::vector<int>& Free() const { return free_; }
  std::size_t NumRuns() const { return runs_.size(); }
  std::size_t NumObservations() const { return 4 * samples_; }

  // Σ residual² at (p, w0); per run when `per_run` is given.
  double Cost(const FullParameters& p, const std::vector<Eigen::Vector4d>& w0,
              std::vector<double>* per_run = nullptr) const;

  void Linearize(const FullParameters& p, const std::vector<Eigen::Vector4d>& w0,
                 NormalEquations* ne) const;

  // The w0 of every run minimising the cost for fixed p (a linear least-squares problem). False when
  // a run's system is singular.
  bool SolveInitialStates(const FullParameters& p, std::vector<Eigen::Vector4d>* w0) const;

 private:
  // JᵀJ and Jᵀe of one run over (free parameters, w0), and Σ e².
  void LinearizeRun(std::size_t r, const FullParameters& p, const Eigen::Vector4d& w0,
                    Eigen::MatrixXd* h, Eigen::VectorXd* g, double* cost) const;

  const std::vector<RunData>& runs_;
  std::vector<int> free_;
  std::size_t samples_ = 0;
  int threads_ = 1;
};

// x(0) = G⁻¹·w0 and back.
Eigen::Vector4d TrueInitialState(const FullParameters& p, const Eigen::Vector4d& w0);
Eigen::Vector4d ObservedInitialState(const FullParameters& p, const Eigen::Vector4d& x0);

// Eliminates the per-run w0 blocks: H_red = H_pp − Σ H_px·H_xx⁻¹·H_xp. This is the information of
// the free parameters with the initial states as nuisance parameters (per unit noise variance).
bool ReducedInformation(const NormalEquations& ne, Eigen::MatrixXd* h_reduced);

// Solves the Levenberg–Marquardt system (H + λ·diag(H))·Δ = g for the free parameters and every x0,
// through the same Schur complement. False when singular.
bool SolveDamped(const NormalEquations& ne, double lambda, Eigen::VectorXd* dp,
                 std::vector<Eigen::Vector4d>* dx0);

}  // namespace hrgbench::estimator::internal
