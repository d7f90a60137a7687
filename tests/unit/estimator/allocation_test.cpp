// The estimator's sample loops do not allocate (STYLE rule 3). Two independent checks:
//  - this test links the checked build of the library (EIGEN_RUNTIME_NO_MALLOC, assertions on): any
//    Eigen heap allocation inside a NoAllocationScope aborts the test;
//  - a counting global operator new: a pass over the data must allocate the same number of times
//  for
//    1 000 and for 100 000 samples per run (std containers, lambdas, anything else).
#include <gtest/gtest.h>

#include "allocation_counter.hpp"  // the counting operator new (this binary only)
#include "estimator/output_error_problem.hpp"
#include "hrgbench/estimator/simulation.hpp"
#include "hrgbench/estimator/whole_angle_control.hpp"

namespace hrgbench::estimator {
namespace {

std::vector<RunData> Simulate(double duration_s) {
  std::vector<RunPlan> plans;
  for (int k = 0; k < 3; ++k) {
    RunPlan p;
    p.omega_rad_s = 0.3 * (k - 1) + 0.05;
    p.b = 0.1 * k;
    p.theta_rad = 0.4 * k;
    p.sample_rate_hz = 1000.0;
    p.duration_s = duration_s;
    plans.push_back(p);
  }
  SimulationOptions truth;
  truth.delta << -1e-3, 0.3, 1e-6, -2e-6, 3e-6, 1e-6;
  truth.xi << 0.01, -0.002, 0.003, 0.004;
  truth.sigma = 1e-4;
  return SimulateRuns(plans, truth);
}

// Allocations made by one call of each pass, single-threaded.
long CountPass(const std::vector<RunData>& runs) {
  const RunsInMemory run_set(runs);
  const internal::OutputErrorProblem problem(run_set, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9}, 1);
  internal::FullParameters p;
  p << -1e-3, 0.3, 1e-6, -2e-6, 3e-6, 1e-6, 0.01, -0.002, 0.003, 0.004;
  std::vector<internal::RunNuisance> w0;
  internal::NormalEquations ne;
  std::vector<double> per_run;
  const long before = hrgbench::testing::process_allocation_count.load();
  EXPECT_TRUE(problem.SolveInitialStates(p, &w0));
  problem.Linearize(p, w0, &ne);
  problem.Cost(p, w0, &per_run);
  return hrgbench::testing::process_allocation_count.load() - before;
}

TEST(AllocationTest, PassesOverTheDataAllocateIndependentlyOfTheSampleCount) {
#ifndef EIGEN_RUNTIME_NO_MALLOC
  GTEST_FAIL() << "this test must link hrgbench_estimator_checked";
#endif
  const std::vector<RunData> short_runs = Simulate(1.0);
  const std::vector<RunData> long_runs = Simulate(100.0);
  ASSERT_EQ(long_runs[0].size(), 100 * short_runs[0].size());
  const long short_count = CountPass(short_runs);
  const long long_count = CountPass(long_runs);
  EXPECT_EQ(short_count, long_count);
  EXPECT_GT(short_count, 0);  // the counter works: the passes do allocate their result buffers
}

// The electronics' control step (u = V(y, p)) runs at the sample rate inside the gyro: it must not
// allocate at all.
TEST(AllocationTest, TheWholeAngleControlStepDoesNotAllocate) {
  CompensationSet p = IdentityCompensation(0.3, -1e-3);
  p.xi << 0.01, -0.002, 0.003, 0.004;
  WholeAngleControl control(p, {}, 1e-3);
  const long before = hrgbench::testing::process_allocation_count.load();
  double angle = 0.0;
  for (int k = 0; k < 1000; ++k) {
    const double theta = 1e-3 * k;
    angle = control.Step(Observation(std::cos(theta), 0.0, std::sin(theta), 0.0)).angle_rad;
  }
  EXPECT_EQ(hrgbench::testing::process_allocation_count.load() - before, 0);
  EXPECT_NEAR(angle, 0.999, 0.02);  // it did run: the readout followed the wave
}

}  // namespace
}  // namespace hrgbench::estimator
