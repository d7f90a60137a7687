// Runs less their outliers (src/estimator/cleaned_runs.hpp): removals in two passes, each given in
// the indices of the run as it then was, leave the samples a direct removal of the union leaves,
// whether the copies are kept (runs in memory) or remade on each load (a set that keeps nothing).
#include "estimator/cleaned_runs.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace hrgbench::estimator::internal {
namespace {

// Runs whose samples are numbered: t_s[k] = k, y(:, k) = (k, 10k, 100k, 1000k).
std::vector<RunData> Numbered(int runs, int samples) {
  std::vector<RunData> out(static_cast<std::size_t>(runs));
  for (int r = 0; r < runs; ++r) {
    RunData& run = out[static_cast<std::size_t>(r)];
    run.id = r + 1;
    run.omega_rad_s = 0.1 * (r + 1);
    run.y.resize(4, samples);
    for (int k = 0; k < samples; ++k) {
      run.t_s.push_back(k);
      run.y.col(k) << k, 10.0 * k, 100.0 * k, 1000.0 * k;
    }
  }
  return out;
}

// The same runs, claiming not to be in memory (as a spool that keeps nothing).
class NotKept final : public RunSet {
 public:
  explicit NotKept(const std::vector<RunData>& runs) : runs_(runs) {}
  std::size_t size() const override { return runs_.size(); }
  const RunInfo& Info(std::size_t r) const override { return runs_.Info(r); }
  RunPtr Load(std::size_t r) const override {
    ++loads;
    return runs_.Load(r);
  }
  bool InMemory() const override { return false; }
  mutable int loads = 0;

 private:
  RunsInMemory runs_;
};

// The sample numbers (t_s) run 1 holds.
std::vector<double> Kept(const RunSet& runs) { return runs.Load(1)->t_s; }

void RemoveInTwoPasses(CleanedRuns* cleaned) {
  // First pass: samples 2, 5, 6 of run 1 (of 0 … 9).
  cleaned->Remove(1, {2, 5, 6});
  // Second pass, in the indices of what is left (0 1 3 4 7 8 9): 0, 3 and 6 are samples 0, 4, 9.
  cleaned->Remove(1, {0, 3, 6});
}

TEST(CleanedRunsTest, TwoPassesRemoveTheUnionInTheCallersIndices) {
  const std::vector<RunData> runs = Numbered(3, 10);
  const std::vector<double> expected = {1, 3, 7, 8};
  for (const bool kept : {true, false}) {
    const RunsInMemory in_memory(runs);
    const NotKept not_kept(runs);
    const RunSet& base = kept ? static_cast<const RunSet&>(in_memory) : not_kept;
    CleanedRuns cleaned(base);
    RemoveInTwoPasses(&cleaned);
    EXPECT_EQ(Kept(cleaned), expected) << (kept ? "kept" : "remade");
    EXPECT_EQ(cleaned.Info(1).samples, 4);
    const RunPtr run = cleaned.Load(1);
    for (Eigen::Index k = 0; k < run->size(); ++k)
      EXPECT_EQ(run->y(3, k), 1000.0 * run->t_s[static_cast<std::size_t>(k)]);
    // The other runs are the caller's, untouched.
    EXPECT_EQ(cleaned.Load(0).get(), &runs[0]);
    EXPECT_EQ(cleaned.Info(2).samples, 10);
    EXPECT_EQ(cleaned.InMemory(), kept);
  }
}

TEST(CleanedRunsTest, OverASetThatKeepsNothingTheCopyIsRemadeOnEachLoad) {
  const std::vector<RunData> runs = Numbered(2, 10);
  const NotKept not_kept(runs);
  CleanedRuns cleaned(not_kept);
  RemoveInTwoPasses(&cleaned);
  const int before = not_kept.loads;
  const RunPtr a = cleaned.Load(1);
  const RunPtr b = cleaned.Load(1);
  EXPECT_NE(a.get(), b.get());
  EXPECT_EQ(not_kept.loads, before + 2);
  EXPECT_EQ(a->t_s, b->t_s);
}

}  // namespace
}  // namespace hrgbench::estimator::internal
