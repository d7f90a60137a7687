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
// Each run has its own nuisance parameters, eliminated like w0: besides w0, optionally
//  - the coefficients q_1 … q_D of a common phase ψ(t) of both channels (common_phase.hpp): the
//    model becomes y = e^{iψ(t)}·G·exp(A·t)·G⁻¹·w0, invariant to what the demodulation reference's
//    phase and frequency do, up to degree D;
//  - an offset ΔΩ of the run's rate from the recorded one, with a Gaussian prior of std σ_Ω (the
//    recorded standard error of Ω): a pseudo-observation ΔΩ = 0 of weight σ²/σ_Ω², so the
//    uncertainty of Ω enters the covariance of (δ, ξ), and a recorded Ω the data contradict shows
//    up as a large fitted ΔΩ/σ_Ω.
//
// Linearize() accumulates the normal equations JᵀJ, Jᵀr in the block structure the problem has (the
// nuisance of one run touches only that run's samples), so the per-run blocks can be eliminated by
// a Schur complement: the cost is linear in the number of samples, and the linear algebra is at
// most 18×18. The sample loop works on buffers sized before it starts; it does not allocate.
//
// Internal to the estimator library.

#include <Eigen/Core>
#include <vector>

#include "hrgbench/estimator/parameters.hpp"
#include "hrgbench/estimator/run_data.hpp"
#include "hrgbench/estimator/run_set.hpp"

namespace hrgbench::estimator::internal {

using FullParameters = Eigen::Matrix<double, 10, 1>;  // (δ1…δ6, ξ1…ξ4)
inline constexpr int kXiOffset = 6;

FullParameters Pack(const Delta& delta, const Xi& xi);

// What each run's nuisance vector holds: w0 (4), then q_1 … q_D, then ΔΩ when Ω is a nuisance of
// that run (omega_prior_weight[r] > 0).
struct NuisanceModel {
  int phase_degree = 0;                    // D, 0 … kMaxPhaseDegree
  std::vector<double> omega_prior_weight;  // per run: σ̂²/σ_Ω² (cost units); empty or 0 = Ω held

  bool OmegaFree(std::size_t run) const {
    return run < omega_prior_weight.size() && omega_prior_weight[run] > 0.0;
  }
  int Size(std::size_t run) const { return 4 + phase_degree + (OmegaFree(run) ? 1 : 0); }
  static int PhaseIndex(int j) { return 3 + j; }  // q_j, j = 1 … D
  int OmegaIndex() const { return 4 + phase_degree; }
};

// Per-run nuisance parameters, laid out as NuisanceModel says.
using RunNuisance = Eigen::VectorXd;

struct NormalEquations {
  Eigen::MatrixXd h_pp;               // free × free
  Eigen::VectorXd g_p;                // Jᵀ·residual, free part
  std::vector<Eigen::MatrixXd> h_px;  // per run, free × nuisance
  std::vector<Eigen::MatrixXd> h_xx;  // per run, nuisance × nuisance
  std::vector<Eigen::VectorXd> g_x;   // per run
  double cost = 0.0;                  // Σ residual² (+ the Ω priors)
  std::vector<double> cost_per_run;   // Σ residual² of each run's samples (no prior)
  // Where it was linearised, and each run's Gram sums S_mn = Σ_k conj(c_m)·c_n of the basis
  // functions there (output_error_problem.cpp): the information of any other choice of columns
  // at that point follows from them without a pass over the data (InformationAt).
  FullParameters p = FullParameters::Zero();
  std::vector<RunNuisance> nuisance;
  std::vector<Eigen::MatrixXcd> gram;
};

// The cost at the initial states SolveInitialStates found, from its normal equations:
// Σ|y|² − Re(b^H·u0) per run (+ the Ω priors), which cancels against Σ|y|² (`data_norm2`): its
// rounding error is ~1e-16·n·data_norm2 at worst, so it ranks two points only when their costs
// differ by more than that.
struct InitialStatesCost {
  double cost = 0.0;
  double data_norm2 = 0.0;
};

class OutputErrorProblem {
 public:
  // `free` lists the estimated entries of FullParameters, ascending. `runs` must outlive this.
  // `threads`: 0 = all hardware threads, 1 = none created; runs are spread over them, and only
  // when the runs hold at least `min_samples_for_threads` samples (MlOptions says why).
  OutputErrorProblem(const RunSet& runs, std::vector<int> free, int threads = 1,
                     std::size_t min_samples_for_threads = 0, NuisanceModel nuisance = {});

  int NumFree() const { return static_cast<int>(free_.size()); }
  int Threads() const { return threads_; }
  const std::vector<int>& Free() const { return free_; }
  std::size_t NumRuns() const { return runs_.size(); }
  std::size_t NumObservations() const { return 4 * samples_; }
  const NuisanceModel& Nuisance() const { return nuisance_; }
  // Σ over runs of the nuisance parameters, less the Ω priors' pseudo-observations.
  int NumNuisanceDegreesOfFreedom() const;

  // Σ residual² (+ the Ω priors) at (p, nuisance); per run (samples only) when `per_run` is given.
  double Cost(const FullParameters& p, const std::vector<RunNuisance>& nuisance,
              std::vector<double>* per_run = nullptr) const;

  void Linearize(const FullParameters& p, const std::vector<RunNuisance>& nuisance,
                 NormalEquations* ne) const;

  // The information JᵀJ of this problem's columns at the point `linearized` was taken at (its p;
  // `nuisance`, that point's nuisance laid out as this problem's model says), from its Gram sums:
  // no pass over the data. Why: a problem with other columns over the same basis — Ω as one more
  // nuisance — needs its information where the fit ended, and a linearisation is a whole pass.
  // The gradient is left zero and the cost is `linearized`'s (both need the residuals). False when
  // `linearized` has no Gram sums for this problem's runs and common phase.
  bool InformationAt(const NormalEquations& linearized, const std::vector<RunNuisance>& nuisance,
                     NormalEquations* ne) const;

  // The w0 of every run minimising the cost for fixed p and the other nuisance parameters (a linear
  // least-squares problem); a nuisance vector of the wrong size is first reset to zeros. False when
  // a run's system is singular.
  // When `cost` is given, it receives the cost at the solution from the normal equations.
  // `samples_per_run` > 0: each run's w0 from every s-th sample only, s = ⌊n/samples_per_run⌋
  // (at least 1), and the cost over those samples. Why: the model is linear in w0, so a w0 that
  // is only near its optimum costs a Gauss–Newton step nothing (the step solves w0 exactly), and
  // telling two starting points apart needs far fewer samples than a fit.
  bool SolveInitialStates(const FullParameters& p, std::vector<RunNuisance>* nuisance,
                          InitialStatesCost* cost = nullptr,
                          Eigen::Index samples_per_run = 0) const;

  // Residuals y − ŷ of run r, one column per sample.
  void RunResiduals(std::size_t r, const FullParameters& p, const RunNuisance& nuisance,
                    Eigen::Matrix4Xd* residuals) const;

  // Jᵀe of run r summed over consecutive blocks of `block_length` samples (the last block takes the
  // remainder): one column per block, rows as Linearize orders them (free parameters, nuisance).
  // Their outer products estimate the covariance of the score under correlated residuals.
  void RunBlockScores(std::size_t r, const FullParameters& p, const RunNuisance& nuisance,
                      std::size_t block_length, Eigen::MatrixXd* block_scores) const;

 private:
  // JᵀJ and Jᵀe of one run over (free parameters, nuisance), and Σ e².
  void LinearizeRun(std::size_t r, const FullParameters& p, const RunNuisance& nuisance,
                    Eigen::MatrixXd* h, Eigen::VectorXd* g, Eigen::MatrixXcd* gram,
                    double* cost) const;
  template <int kBasis>
  void LinearizeRunWithBasis(std::size_t r, const FullParameters& p, const RunNuisance& nuisance,
                             Eigen::MatrixXd* h, Eigen::VectorXd* g, Eigen::MatrixXcd* gram,
                             double* cost) const;
  // Each run's JᵀJ, Jᵀe (free parameters, nuisance) into the blocks of `ne`, with the Ω priors.
  void Assemble(const std::vector<Eigen::MatrixXd>& h, const std::vector<Eigen::VectorXd>& g,
                const std::vector<RunNuisance>& nuisance, NormalEquations* ne) const;

  const RunSet& runs_;
  std::vector<int> free_;
  std::size_t samples_ = 0;
  int threads_ = 1;
  NuisanceModel nuisance_;
};

// x(0) = G⁻¹·w0 and back (w0 = the first four entries of a run's nuisance).
Eigen::Vector4d TrueInitialState(const FullParameters& p, const Eigen::Vector4d& w0);
Eigen::Vector4d ObservedInitialState(const FullParameters& p, const Eigen::Vector4d& x0);

// Eliminates the per-run nuisance blocks: H_red = H_pp − Σ H_px·H_xx⁻¹·H_xp. This is the
// information of the free parameters with the nuisance parameters unknown (per unit noise
// variance).
bool ReducedInformation(const NormalEquations& ne, Eigen::MatrixXd* h_reduced);

// H_px·H_xx⁻¹ of each run: maps a run's score onto the reduced score of the free parameters,
// s_red = s_p − K·s_x.
bool NuisanceProjections(const NormalEquations& ne, std::vector<Eigen::MatrixXd>* k);

// Solves the Levenberg–Marquardt system (H + λ·diag(H))·Δ = g for the free parameters and every
// run's nuisance, through the same Schur complement. False when singular.
bool SolveDamped(const NormalEquations& ne, double lambda, Eigen::VectorXd* dp,
                 std::vector<RunNuisance>* dx);

}  // namespace hrgbench::estimator::internal
