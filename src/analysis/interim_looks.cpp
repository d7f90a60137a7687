#include "hrgbench/analysis/interim_looks.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

#include "hrgbench/config/decision_rule.hpp"

namespace hrgbench::bench {
namespace {

// W's density is followed down to this many of its std below zero: the mass beyond is < 1e-18.
constexpr double kLowerStd = 9.0;
// The Gaussian kernel between looks is cut at this many of its std.
constexpr double kKernelStd = 9.0;

double NormalDensity(double x) noexcept {
  return std::exp(-0.5 * x * x) / std::sqrt(2.0 * std::numbers::pi);
}

// The density of W(t_j) over paths that have not crossed, on the points b − (n − i)·h,
// i = 0 … n (n even): the boundary b is the last point, every grid has the same step h. The
// density is integrated by Simpson's rule: it is smooth up to b, where the boundary cuts it, and
// the trapezoid's O(h²) error there put k_i 0.01 high at a grid of four points per std.
struct Grid {
  double b = 0.0;
  double h = 0.0;
  std::vector<double> density;

  std::size_t n() const { return density.size() - 1; }
  double At(std::size_t i) const { return b - h * static_cast<double>(n() - i); }
  // Simpson's weight of point i (times h).
  double Weight(std::size_t i) const {
    if (i == 0 || i == n()) return 1.0 / 3.0;
    return (i % 2 == 1 ? 4.0 : 2.0) / 3.0;
  }
  // ∫ density from the lowest point to b.
  double Mass() const {
    double sum = 0.0;
    for (std::size_t i = 0; i < density.size(); ++i) sum += Weight(i) * density[i];
    return sum * h;
  }
};

Grid Spanning(double lo, double b, double h) {
  Grid grid;
  grid.b = b;
  grid.h = h;
  auto intervals = static_cast<std::size_t>(std::max(2.0, std::ceil((b - lo) / h)));
  intervals += intervals % 2;
  grid.density.assign(intervals + 1, 0.0);
  return grid;
}

}  // namespace

double NormalTail(double z) noexcept { return 0.5 * std::erfc(z / std::numbers::sqrt2); }

double CrossingProbability(double c, std::span<const double> t) {
  if (t.empty()) return 0.0;
  // The grid step resolves the narrowest Gaussian of the recursion (the first look's spread, and
  // the spread between the closest looks) with eight points per std.
  double narrowest = std::sqrt(t[0]);
  for (std::size_t j = 1; j < t.size(); ++j)
    narrowest = std::min(narrowest, std::sqrt(t[j] - t[j - 1]));
  const double step = narrowest / 8.0;
  const auto boundary = [&](std::size_t j) { return c * std::sqrt(t[j]); };

  Grid grid = Spanning(-kLowerStd * std::sqrt(t[0]), boundary(0), step);
  const double s0 = std::sqrt(t[0]);
  for (std::size_t i = 0; i < grid.density.size(); ++i)
    grid.density[i] = NormalDensity(grid.At(i) / s0) / s0;
  std::vector<double> kernel;
  for (std::size_t j = 1; j < t.size(); ++j) {
    const double sigma = std::sqrt(t[j] - t[j - 1]);
    Grid next = Spanning(-kLowerStd * std::sqrt(t[j]), boundary(j), step);
    // Both grids share the step, so a point of `next` minus a point of `grid` is
    // (b' − b) + d·h for the integer d = m − i + n − n': the kernel is tabulated over d once.
    const double shift = next.b - grid.b;
    const auto offset =
        static_cast<std::ptrdiff_t>(grid.n()) - static_cast<std::ptrdiff_t>(next.n());
    const auto d_min = static_cast<std::ptrdiff_t>(std::ceil((-kKernelStd * sigma - shift) / step));
    const auto d_max = static_cast<std::ptrdiff_t>(std::floor((kKernelStd * sigma - shift) / step));
    kernel.clear();
    for (std::ptrdiff_t d = d_min; d <= d_max; ++d)
      kernel.push_back(NormalDensity((shift + static_cast<double>(d) * step) / sigma) / sigma);
    const std::vector<double> weighted = [&] {
      std::vector<double> w(grid.density);
      for (std::size_t i = 0; i < w.size(); ++i) w[i] *= grid.Weight(i);
      return w;
    }();
    const auto last_i = static_cast<std::ptrdiff_t>(grid.n());
    for (std::size_t m = 0; m < next.density.size(); ++m) {
      // d = m − i + offset within [d_min, d_max]  ⇔  i within [m + offset − d_max, m + offset −
      // d_min].
      const auto base = static_cast<std::ptrdiff_t>(m) + offset;
      const std::ptrdiff_t i_lo = std::max<std::ptrdiff_t>(0, base - d_max);
      const std::ptrdiff_t i_hi = std::min(last_i, base - d_min);
      double sum = 0.0;
      for (std::ptrdiff_t i = i_lo; i <= i_hi; ++i)
        sum += weighted[static_cast<std::size_t>(i)] *
               kernel[static_cast<std::size_t>(base - i - d_min)];
      next.density[m] = sum * step;
    }
    grid = std::move(next);
  }
  return std::clamp(1.0 - grid.Mass(), 0.0, 1.0);
}

double InterimCoverageFactor(double k, std::span<const double> t) {
  if (t.size() < 2) return k;
  const double target = NormalTail(k);
  if (CrossingProbability(kMaxCoverageFactor, t) >= target) return kMaxCoverageFactor;
  // log P(c) − log target falls smoothly from ≥ 0 at c = k to < 0 at the bound: bracketed false
  // position (Illinois) to 1e-7 in c, a handful of integrations where bisection takes two dozen.
  const auto f = [&](double c) { return std::log(CrossingProbability(c, t)) - std::log(target); };
  double a = k, fa = f(a), b = kMaxCoverageFactor, fb = f(b);
  if (fa <= 0.0) return k;
  int side = 0;
  for (int i = 0; i < 100 && b - a > 1e-7; ++i) {
    const double c = std::clamp((a * fb - b * fa) / (fb - fa), a, b);
    const double fc = f(c);
    if (fc > 0.0) {
      a = c;
      fa = fc;
      if (side == 1) fb *= 0.5;
      side = 1;
    } else {
      b = c;
      fb = fc;
      if (side == -1) fa *= 0.5;
      side = -1;
    }
    if (fc == 0.0) return c;
  }
  return std::clamp(0.5 * (a + b), k, kMaxCoverageFactor);
}

}  // namespace hrgbench::bench
