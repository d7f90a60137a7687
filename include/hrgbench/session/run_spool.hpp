#pragma once
// The runs of an estimate kept within a memory budget: runs are added as the session is read
// (session::ReadEachRun), the first ones kept in memory while they fit in the budget, every later
// one written to a scratch file and read back whenever a pass of the fit loads it. The fit holds a
// loaded run for its turn only (estimator/run_set.hpp), so an estimate's samples take at most the
// budget plus one run per estimator thread, whatever the session's length
// (docs/estimator/methods.md "Memory").
//
// Why a fixed split and not a cache: every pass of the fit reads the runs in the same order, and a
// least-recently-used cache smaller than the session evicts each run just before the next pass
// wants it (it would hold the budget's worth of runs and still read every one). Kept runs are never
// read; spooled runs are read once per pass, at the speed of a copy from the page cache.
//
// The scratch file is unlinked as soon as it is made (nothing is left behind, even on a crash) and
// created only when the first run does not fit: a session within the budget never touches a disk.
// Runs are written as the raw doubles of t_s and y, so a run read back is bit-identical.

#include <cstddef>
#include <cstdint>
#include <expected>
#include <filesystem>
#include <memory>
#include <mutex>
#include <vector>

#include "hrgbench/estimator/run_data.hpp"
#include "hrgbench/estimator/run_set.hpp"
#include "hrgbench/session/session.hpp"

namespace hrgbench::session {

// The bytes a run's samples take in memory (t_s and y: 40 per sample).
std::size_t RunSampleBytes(const estimator::RunData& run);

class RunSpool final : public estimator::RunSet {
 public:
  // `memory_budget_bytes`: how much of the runs' samples stays in memory between loads (0: none;
  // a run in use is held whatever its size). `scratch_dir`: where the scratch file goes (empty:
  // std::filesystem::temp_directory_path(), which honours TMPDIR).
  explicit RunSpool(std::size_t memory_budget_bytes, std::filesystem::path scratch_dir = {});
  ~RunSpool() override;
  RunSpool(const RunSpool&) = delete;
  RunSpool& operator=(const RunSpool&) = delete;

  // Takes the next run. An error (naming the scratch directory or file) when the scratch file
  // cannot be made or written; the spool is then unchanged.
  std::expected<void, SessionError> Add(estimator::RunData&& run);

  std::size_t size() const override { return runs_.size(); }
  const estimator::RunInfo& Info(std::size_t r) const override { return runs_[r].info; }
  // A kept run, the run a pass already holds, or the run read back from the scratch file (throws
  // std::system_error when the read fails). The spool must outlive every run it hands out.
  estimator::RunPtr Load(std::size_t r) const override;
  bool InMemory() const override { return spooled_runs_ == 0; }

  // What the spool did, for the tests and the measurements.
  struct Counts {
    std::size_t kept_runs = 0;
    std::size_t kept_bytes = 0;
    std::size_t spooled_runs = 0;
    std::size_t bytes_written = 0;
    std::size_t reads = 0;  // runs read back from the scratch file
    std::size_t bytes_read = 0;
  };
  Counts counts() const;

 private:
  struct Entry {
    estimator::RunInfo info;
    estimator::RunPtr kept;    // in memory for the spool's life, or null
    std::int64_t offset = -1;  // in the scratch file, when spooled
    mutable std::weak_ptr<const estimator::RunData> in_use;  // a spooled run some pass holds
  };

  std::expected<void, SessionError> OpenScratch();
  // A buffer for a run read back: a recycled one when there is one. Runs let go are recycled (up
  // to kRecycled of them): a run's arrays are megabytes, and allocated afresh on every load each
  // page of them would fault in again (the kernel zeroes it) on every pass.
  std::unique_ptr<estimator::RunData> Buffer() const;
  void Recycle(const estimator::RunData* run) const;
  static constexpr std::size_t kRecycled = 2;

  std::size_t budget_;
  std::filesystem::path scratch_dir_;
  std::vector<Entry> runs_;
  std::size_t kept_bytes_ = 0;
  std::size_t spooled_runs_ = 0;
  std::size_t bytes_written_ = 0;
  int fd_ = -1;
  std::int64_t end_ = 0;
  mutable std::mutex mutex_;  // guards each entry's in_use, the recycled buffers, the read counts
  mutable std::vector<std::unique_ptr<estimator::RunData>> recycled_;
  mutable std::size_t reads_ = 0;
  mutable std::size_t bytes_read_ = 0;
};

}  // namespace hrgbench::session
