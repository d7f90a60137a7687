#pragma once
// Runs with samples removed (the fit's outliers), as a run set over the caller's runs. Over runs in
// memory a run's copy without them is kept; over a set that keeps nothing (a spool, run_set.hpp)
// the copy is remade from the run and the removed samples' indices whenever it is loaded, so the
// fit's memory stays that of the runs in use, outliers or not.
//
// Internal to the estimator library.

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "hrgbench/estimator/run_data.hpp"
#include "hrgbench/estimator/run_set.hpp"

namespace hrgbench::estimator::internal {

// The samples of `run` without those listed (ascending).
inline RunData WithoutSamples(const RunData& run, const std::vector<Eigen::Index>& removed) {
  RunData kept;
  kept.id = run.id;
  kept.omega_rad_s = run.omega_rad_s;
  kept.omega_std_rad_s = run.omega_std_rad_s;
  const Eigen::Index n = run.size() - static_cast<Eigen::Index>(removed.size());
  kept.t_s.reserve(static_cast<std::size_t>(n));
  kept.y.resize(4, n);
  std::size_t next = 0;
  Eigen::Index out = 0;
  for (Eigen::Index k = 0; k < run.size(); ++k) {
    if (next < removed.size() && removed[next] == k) {
      ++next;
      continue;
    }
    kept.t_s.push_back(run.t_s[static_cast<std::size_t>(k)]);
    kept.y.col(out++) = run.y.col(k);
  }
  return kept;
}

class CleanedRuns final : public RunSet {
 public:
  explicit CleanedRuns(const RunSet& runs)
      : runs_(runs), removed_(runs.size()), copies_(runs.size()) {
    info_.reserve(runs.size());
    for (std::size_t r = 0; r < runs.size(); ++r) info_.push_back(runs.Info(r));
  }
  std::size_t size() const override { return runs_.size(); }
  const RunInfo& Info(std::size_t r) const override { return info_[r]; }
  RunPtr Load(std::size_t r) const override {
    if (removed_[r].empty()) return runs_.Load(r);
    if (copies_[r]) return copies_[r];
    return std::make_shared<const RunData>(WithoutSamples(*runs_.Load(r), removed_[r]));
  }
  bool InMemory() const override { return runs_.InMemory(); }

  // Removes run r's samples `now` (ascending indices into the run as Load returns it now).
  void Remove(std::size_t r, const std::vector<Eigen::Index>& now) {
    if (now.empty()) return;
    if (runs_.InMemory())
      copies_[r] = std::make_shared<const RunData>(WithoutSamples(*Load(r), now));
    // `now` indexes the run less what was removed before: in the caller's run's indices,
    // merged with those.
    std::vector<Eigen::Index>& removed = removed_[r];
    std::vector<Eigen::Index> merged;
    merged.reserve(removed.size() + now.size());
    std::size_t before = 0, next = 0;
    Eigen::Index kept = 0;
    for (Eigen::Index k = 0; k < runs_.Info(r).samples && next < now.size(); ++k) {
      if (before < removed.size() && removed[before] == k) {
        merged.push_back(k);
        ++before;
        continue;
      }
      if (kept++ == now[next]) {
        merged.push_back(k);
        ++next;
      }
    }
    merged.insert(merged.end(), removed.begin() + static_cast<std::ptrdiff_t>(before),
                  removed.end());
    removed = std::move(merged);
    info_[r].samples = runs_.Info(r).samples - static_cast<Eigen::Index>(removed.size());
  }

 private:
  const RunSet& runs_;
  std::vector<RunInfo> info_;
  std::vector<std::vector<Eigen::Index>> removed_;  // per run, ascending, the caller's indices
  std::vector<RunPtr> copies_;                      // per run, when kept
};

}  // namespace hrgbench::estimator::internal
