#pragma once
// The runs a fit takes, as a set it reads run by run. Every pass of the estimator over the data is
// a loop over runs (ParallelFor), and a run's samples are needed only while its turn lasts: so the
// samples need not all be in memory at once. RunsInMemory is the caller's vector; a set kept
// elsewhere (the session layer's spool, session/run_spool.hpp) brings a run in when it is loaded
// and lets it go when no pass holds it, so an estimate's memory is bounded by the runs in use, not
// by the session (docs/estimator/methods.md "Memory").
//
// The estimator's passes hold a loaded run (RunPtr) for one run's turn and load it again on the
// next pass: a set that keeps nothing between passes reads every run once per pass.

#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <memory>
#include <vector>

#include "hrgbench/estimator/run_data.hpp"

namespace hrgbench::estimator {

// What a fit needs to know of a run without its samples.
struct RunInfo {
  int id = 0;
  double omega_rad_s = 0.0;
  double omega_std_rad_s = std::numeric_limits<double>::quiet_NaN();
  Eigen::Index samples = 0;

  static RunInfo Of(const RunData& run) {
    return {run.id, run.omega_rad_s, run.omega_std_rad_s, run.size()};
  }
};

// A loaded run: its samples stay valid while it is held.
using RunPtr = std::shared_ptr<const RunData>;

class RunSet {
 public:
  virtual ~RunSet() = default;
  virtual std::size_t size() const = 0;
  virtual const RunInfo& Info(std::size_t r) const = 0;
  // Run r (0 ≤ r < size()). Safe to call from several threads at once. A set that cannot read a
  // run it holds (an I/O error on its own storage) throws std::system_error.
  virtual RunPtr Load(std::size_t r) const = 0;
  // True when every run is in memory for the set's lifetime (a Load costs nothing): a fit may then
  // keep copies of runs it changes (outliers removed); otherwise it remakes them when it needs
  // them.
  virtual bool InMemory() const = 0;

  std::size_t TotalSamples() const {
    std::size_t n = 0;
    for (std::size_t r = 0; r < size(); ++r) n += static_cast<std::size_t>(Info(r).samples);
    return n;
  }
};

// The caller's runs, which must outlive the set; Load hands out the caller's objects (no copy, no
// ownership).
class RunsInMemory final : public RunSet {
 public:
  explicit RunsInMemory(const std::vector<RunData>& runs) : runs_(runs) {
    info_.reserve(runs.size());
    for (const RunData& run : runs) info_.push_back(RunInfo::Of(run));
  }
  std::size_t size() const override { return runs_.size(); }
  const RunInfo& Info(std::size_t r) const override { return info_[r]; }
  RunPtr Load(std::size_t r) const override { return RunPtr(RunPtr(), &runs_[r]); }
  bool InMemory() const override { return true; }

 private:
  const std::vector<RunData>& runs_;
  std::vector<RunInfo> info_;
};

}  // namespace hrgbench::estimator
