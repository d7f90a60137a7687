#include "hrgbench/report/decimate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hrgbench::report {

MinMaxDecimator::MinMaxDecimator(const std::vector<double>& t_s, std::size_t max_points)
    : n_(t_s.size()) {
  max_points = std::max<std::size_t>(2, max_points);
  if (n_ <= max_points) {
    times_ = t_s;
    return;
  }
  decimated_ = true;
  // Equal counts per bucket (the samples are nearly uniform in time; a gap shows as a longer
  // bucket, never as a lost sample).
  const std::size_t buckets = max_points / 2;
  bucket_begin_.reserve(buckets + 1);
  times_.reserve(2 * buckets);
  for (std::size_t b = 0; b <= buckets; ++b) bucket_begin_.push_back(b * n_ / buckets);
  for (std::size_t b = 0; b < buckets; ++b) {
    times_.push_back(t_s[bucket_begin_[b]]);
    times_.push_back(t_s[bucket_begin_[b + 1] - 1]);
  }
}

std::vector<double> MinMaxDecimator::Apply(const double* first, std::ptrdiff_t stride) const {
  std::vector<double> out;
  if (!decimated_) {
    out.resize(n_);
    for (std::size_t k = 0; k < n_; ++k) out[k] = first[static_cast<std::ptrdiff_t>(k) * stride];
    return out;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out.reserve(times_.size());
  for (std::size_t b = 0; b + 1 < bucket_begin_.size(); ++b) {
    double lo = nan, hi = nan;
    std::size_t lo_at = 0, hi_at = 0;
    for (std::size_t k = bucket_begin_[b]; k < bucket_begin_[b + 1]; ++k) {
      const double v = first[static_cast<std::ptrdiff_t>(k) * stride];
      if (std::isnan(v)) continue;
      if (!(v >= lo)) {
        lo = v;
        lo_at = k;
      }
      if (!(v <= hi)) {
        hi = v;
        hi_at = k;
      }
    }
    if (lo_at <= hi_at) {
      out.push_back(lo);
      out.push_back(hi);
    } else {
      out.push_back(hi);
      out.push_back(lo);
    }
  }
  return out;
}

}  // namespace hrgbench::report
