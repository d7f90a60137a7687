#include "hrgbench/analysis/interim_looks.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "hrgbench/config/decision_rule.hpp"

namespace hrgbench::bench {

double NormalTail(double z) noexcept { return 0.5 * std::erfc(z / std::numbers::sqrt2); }

double InterimCoverageFactor(double k, int looks) noexcept {
  if (looks <= 1) return k;
  const double target = NormalTail(k) / looks;
  if (NormalTail(kMaxCoverageFactor) >= target) return kMaxCoverageFactor;
  // The tail falls monotonically: bisect [k, max] to well below any k a file can state.
  double lo = k, hi = kMaxCoverageFactor;
  for (int i = 0; i < 100 && hi - lo > 1e-12; ++i) {
    const double mid = 0.5 * (lo + hi);
    (NormalTail(mid) > target ? lo : hi) = mid;
  }
  return std::clamp(0.5 * (lo + hi), k, kMaxCoverageFactor);
}

}  // namespace hrgbench::bench
