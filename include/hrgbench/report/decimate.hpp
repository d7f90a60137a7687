#pragma once
// Decimation of long series for display that keeps the envelope: the samples are split into
// buckets of consecutive samples and each bucket contributes its minimum and its maximum, in the
// order they occur. A spike of one sample survives (it is its bucket's extreme), which taking
// every k-th sample would drop; a series of n ≤ max_points samples is kept whole.
//
// All series of one run share the bucket boundaries (they share the time stamps), so a run's
// charts need one time axis: MinMaxDecimator::Times(). Pure, thread-safe, allocates its results.

#include <cstddef>
#include <vector>

namespace hrgbench::report {

class MinMaxDecimator {
 public:
  // `t_s` = the run's time stamps; max_points ≥ 2 (smaller values are taken as 2).
  MinMaxDecimator(const std::vector<double>& t_s, std::size_t max_points);

  // The shared time axis: t_s itself when n ≤ max_points, else two entries per bucket (its first
  // and its last time stamp).
  const std::vector<double>& Times() const { return times_; }
  bool Decimated() const { return decimated_; }

  // The series whose k-th sample is first[k·stride] (k < n), decimated onto Times(): per bucket
  // the min and the max, the earlier first. NaN samples are skipped; a bucket with nothing else
  // gives NaN twice.
  std::vector<double> Apply(const double* first, std::ptrdiff_t stride) const;

 private:
  std::size_t n_ = 0;
  bool decimated_ = false;
  std::vector<std::size_t> bucket_begin_;  // bucket b = [begin[b], begin[b + 1])
  std::vector<double> times_;
};

}  // namespace hrgbench::report
