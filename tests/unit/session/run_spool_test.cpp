// The run spool (session/run_spool.hpp): what fits the budget is kept, the rest written and read
// back bit for bit, a run in use is shared rather than read twice, the scratch file leaves nothing
// behind, and a fit on spooled runs is the fit on the same runs in memory, outliers and all.
#include "hrgbench/session/run_spool.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/simulation.hpp"

namespace hrgbench::session {
namespace {

namespace fs = std::filesystem;

// The production design's rates and pattern angles, `seconds` long at `rate_hz`, σ = 1e-4.
std::vector<estimator::RunData> Runs(double seconds, double rate_hz) {
  std::vector<estimator::RunPlan> plans;
  const double omegas[] = {0.1, -0.1, 0.3, -0.3, 1.0, -1.0};
  for (int k = 0; k < 6; ++k) {
    estimator::RunPlan p;
    p.omega_rad_s = omegas[k];
    p.b = 0.1 * (k % 3);
    p.theta_rad = std::numbers::pi * k / 12.0;
    p.sample_rate_hz = rate_hz;
    p.duration_s = seconds;
    plans.push_back(p);
  }
  estimator::SimulationOptions truth;
  truth.delta << -8e-4, 0.31, -1e-6, 2e-6, -3e-6, 1e-6;
  truth.xi << -0.005, 0.002, -0.004, 0.007;
  truth.sigma = 1e-4;
  truth.seed = 7;
  std::vector<estimator::RunData> runs = estimator::SimulateRuns(plans, truth);
  for (std::size_t r = 0; r < runs.size(); ++r) {
    runs[r].id = static_cast<int>(r + 1);
    runs[r].omega_std_rad_s = 1e-6;
  }
  return runs;
}

// A fresh, empty directory under the test's temporary directory.
fs::path EmptyDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("hrgbench-run-spool-test-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void ExpectSameRun(const estimator::RunData& a, const estimator::RunData& b) {
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.omega_rad_s, b.omega_rad_s);
  EXPECT_EQ(a.omega_std_rad_s, b.omega_std_rad_s);
  EXPECT_EQ(a.t_s, b.t_s);
  EXPECT_TRUE(a.y == b.y);
}

TEST(RunSpoolTest, KeepsWhatFitsTheBudgetAndReadsTheRestBackBitForBit) {
  const std::vector<estimator::RunData> runs = Runs(2.0, 1000.0);
  const std::size_t run_bytes = RunSampleBytes(runs[0]);
  ASSERT_EQ(run_bytes, 2000u * 40u);
  const fs::path dir = EmptyDir("keeps");
  RunSpool spool(run_bytes * 5 / 2, dir);  // two runs and a half
  for (const estimator::RunData& run : runs) {
    estimator::RunData copy = run;
    ASSERT_TRUE(spool.Add(std::move(copy)).has_value());
  }
  RunSpool::Counts c = spool.counts();
  EXPECT_EQ(c.kept_runs, 2u);
  EXPECT_EQ(c.kept_bytes, 2 * run_bytes);
  EXPECT_EQ(c.spooled_runs, 4u);
  EXPECT_EQ(c.bytes_written, 4 * run_bytes);
  EXPECT_FALSE(spool.InMemory());
  // The scratch file was unlinked as soon as it was made.
  EXPECT_TRUE(fs::is_empty(dir));

  ASSERT_EQ(spool.size(), runs.size());
  for (std::size_t r = 0; r < runs.size(); ++r) {
    EXPECT_EQ(spool.Info(r).samples, runs[r].size());
    ExpectSameRun(*spool.Load(r), runs[r]);
  }
  c = spool.counts();
  EXPECT_EQ(c.reads, 4u);  // the kept runs are never read
  EXPECT_EQ(c.bytes_read, 4 * run_bytes);

  // A run some pass holds is shared, not read again; once let go it is read again.
  {
    const estimator::RunPtr held = spool.Load(5);
    const estimator::RunPtr again = spool.Load(5);
    EXPECT_EQ(held.get(), again.get());
    EXPECT_EQ(spool.counts().reads, 5u);
  }
  (void)spool.Load(5);
  EXPECT_EQ(spool.counts().reads, 6u);
  fs::remove_all(dir);
}

TEST(RunSpoolTest, WithinTheBudgetNothingIsWritten) {
  const std::vector<estimator::RunData> runs = Runs(1.0, 1000.0);
  RunSpool spool(std::size_t{1} << 30, "/nonexistent-directory-of-hrgbench");
  for (const estimator::RunData& run : runs) {
    estimator::RunData copy = run;
    ASSERT_TRUE(spool.Add(std::move(copy)).has_value());
  }
  EXPECT_TRUE(spool.InMemory());
  EXPECT_EQ(spool.counts().bytes_written, 0u);
  for (std::size_t r = 0; r < runs.size(); ++r) ExpectSameRun(*spool.Load(r), runs[r]);
  EXPECT_EQ(spool.counts().reads, 0u);
}

TEST(RunSpoolTest, AScratchDirectoryThatCannotBeUsedIsNamed) {
  RunSpool spool(0, "/nonexistent-directory-of-hrgbench");
  std::vector<estimator::RunData> runs = Runs(0.1, 1000.0);
  const auto added = spool.Add(std::move(runs[0]));
  ASSERT_FALSE(added.has_value());
  EXPECT_EQ(added.error().file, fs::path("/nonexistent-directory-of-hrgbench"));
  EXPECT_NE(added.error().message.find("scratch file"), std::string::npos)
      << added.error().ToString();
  EXPECT_EQ(spool.size(), 0u);
}

// Every estimate, its std and its diagnostics the same to the bit whether the runs are in memory
// or read back on every pass; with spikes in two runs, so the outliers' removal (remade from the
// run and the removed indices on each load when nothing is kept) is in it.
TEST(RunSpoolTest, AFitOnSpooledRunsIsTheFitInMemory) {
  std::vector<estimator::RunData> runs = Runs(20.0, 200.0);
  runs[1].y(0, 500) += 0.01;  // 100 σ
  runs[1].y(3, 2500) -= 0.02;
  runs[4].y(2, 40) += 0.015;
  estimator::MlOptions options;
  options.num_threads = 2;
  options.min_samples_for_threads = 0;
  const estimator::EstimateSummary in_memory = estimator::EstimateMaximumLikelihood(runs, options);
  ASSERT_TRUE(in_memory.IsUsable()) << in_memory.Report();

  const fs::path dir = EmptyDir("fit");
  RunSpool spool(0, dir);
  for (const estimator::RunData& run : runs) {
    estimator::RunData copy = run;
    ASSERT_TRUE(spool.Add(std::move(copy)).has_value());
  }
  const estimator::EstimateSummary spooled = estimator::EstimateMaximumLikelihood(spool, options);
  ASSERT_TRUE(spooled.IsUsable()) << spooled.Report();

  EXPECT_TRUE(spooled.delta == in_memory.delta);
  EXPECT_TRUE(spooled.xi == in_memory.xi);
  EXPECT_TRUE(spooled.delta_std == in_memory.delta_std);
  EXPECT_TRUE(spooled.xi_std == in_memory.xi_std);
  EXPECT_TRUE(spooled.covariance == in_memory.covariance);
  EXPECT_EQ(spooled.iterations, in_memory.iterations);
  EXPECT_EQ(spooled.samples_used, in_memory.samples_used);
  EXPECT_EQ(spooled.residual_rms, in_memory.residual_rms);
  ASSERT_EQ(spooled.diagnostics.runs.size(), in_memory.diagnostics.runs.size());
  std::size_t removed = 0;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const estimator::RunFitDiagnostics& a = spooled.diagnostics.runs[r];
    const estimator::RunFitDiagnostics& b = in_memory.diagnostics.runs[r];
    EXPECT_EQ(a.samples, b.samples) << "run " << r + 1;
    EXPECT_EQ(a.outliers_removed, b.outliers_removed) << "run " << r + 1;
    EXPECT_EQ(a.residual_ratio, b.residual_ratio) << "run " << r + 1;
    EXPECT_EQ(a.whiteness_z, b.whiteness_z) << "run " << r + 1;
    removed += a.outliers_removed;
  }
  EXPECT_GE(removed, 3u);  // the spikes were found, so the cleaned runs were used
  EXPECT_EQ(spooled.warnings, in_memory.warnings);
  // Nothing kept: every pass read every run (validation, noise, the start, each linearisation).
  EXPECT_GE(spool.counts().reads, 5 * runs.size());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hrgbench::session
