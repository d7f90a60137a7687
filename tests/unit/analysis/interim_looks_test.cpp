// The interim looks' coverage factor (analysis/interim_looks.hpp), against what does not share its
// code: Pocock's constants for equally spaced looks (Jennison & Turnbull 2000, Table 2.1, two-sided
// α = 0.05, which differ from the one-sided 0.025 boundary by far less than the tolerance), the
// bivariate normal integral for two looks (a one-dimensional quadrature written here), and a
// Monte Carlo of the Brownian motion the looks see.

#include "hrgbench/analysis/interim_looks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "hrgbench/config/decision_rule.hpp"

namespace hrgbench::bench {
namespace {

constexpr double kZ975 = 1.959963984540054;  // Φ⁻¹(0.975): one look risks 2.5 %

std::vector<double> EquallySpaced(int looks) {
  std::vector<double> t;
  for (int j = 1; j <= looks; ++j) t.push_back(static_cast<double>(j) / looks);
  return t;
}

TEST(InterimLooks, EquallySpacedLooksTakePococksBoundary) {
  const double pocock[] = {2.178, 2.289, 2.361, 2.413, 2.453, 2.485, 2.512, 2.535, 2.555};
  for (int looks = 2; looks <= 10; ++looks) {
    EXPECT_NEAR(InterimCoverageFactor(kZ975, EquallySpaced(looks)), pocock[looks - 2], 1.5e-3)
        << looks << " looks";
  }
}

TEST(InterimLooks, TwoLooksCrossAsTheBivariateNormalSays) {
  // P(z1 ≥ c or z2 ≥ c) = 1 − ∫_{−∞}^{c} φ(x) Φ((c − ρx)/√(1 − ρ²)) dx, ρ = √(t1/t2).
  const auto Phi = [](double x) { return 0.5 * std::erfc(-x / std::numbers::sqrt2); };
  const auto exact = [&](double c, double rho) {
    const int n = 40000;
    const double lo = -12.0, h = (c - lo) / n;
    double sum = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double x = lo + h * i;
      const double w = (i == 0 || i == n) ? 0.5 : 1.0;
      sum += w * std::exp(-0.5 * x * x) / std::sqrt(2 * std::numbers::pi) *
             Phi((c - rho * x) / std::sqrt(1 - rho * rho));
    }
    return 1.0 - sum * h;
  };
  for (const double t1 : {0.1, 0.3, 0.5, 0.9}) {
    const std::vector<double> t = {t1, 1.0};
    for (const double c : {2.0, 2.5, 3.0})
      EXPECT_NEAR(CrossingProbability(c, t) / exact(c, std::sqrt(t1)), 1.0, 2e-4)
          << "t1 = " << t1 << ", c = " << c;
  }
}

TEST(InterimLooks, ManyLooksOfAnAdaptiveSequenceRiskWhatOneLookRisks) {
  // 115 uneven looks: every 5 s within and after each run of 20 s, then of 80 s, from the second.
  std::vector<double> t;
  double before = 0.0;
  for (const double length :
       {20.0, 20.0, 20.0, 20.0, 20.0, 20.0, 80.0, 80.0, 80.0, 80.0, 80.0, 80.0}) {
    const bool may_decide = before > 0.0;  // from the second run on
    for (double at = 5.0; may_decide && at <= length - 2.5; at += 5.0)
      t.push_back((before + at) / 600.0);
    before += length;
    if (may_decide && before < 600.0) t.push_back(before / 600.0);
  }
  ASSERT_EQ(t.size(), 115u);
  const double k_i = InterimCoverageFactor(2.0, t);
  // Far below Bonferroni's 3.55 (looks · tail(k_i) = tail(2)), above one look's 2.
  EXPECT_GT(k_i, 2.3);
  EXPECT_LT(k_i, 3.2);
  // A Monte Carlo of W at the looks: the boundary is crossed as often as one look at k = 2 errs.
  std::mt19937_64 random(20261201);
  std::normal_distribution<double> normal;
  const int paths = 200000;
  int crossed = 0;
  for (int p = 0; p < paths; ++p) {
    double w = 0.0, previous = 0.0;
    for (const double tj : t) {
      w += std::sqrt(tj - previous) * normal(random);
      previous = tj;
      if (w / std::sqrt(tj) >= k_i) {
        ++crossed;
        break;
      }
    }
  }
  // tail(2) = 0.02275; the Monte Carlo's std is 3.3e-4.
  EXPECT_NEAR(static_cast<double>(crossed) / paths, NormalTail(2.0), 1.4e-3);
}

TEST(InterimLooks, FewerThanTwoLooksAreTheFileKAndNoneIsBeyondTheBound) {
  EXPECT_EQ(InterimCoverageFactor(2.0, std::vector<double>{}), 2.0);
  EXPECT_EQ(InterimCoverageFactor(2.0, std::vector<double>{0.4}), 2.0);
  EXPECT_EQ(InterimCoverageFactor(kMaxCoverageFactor, EquallySpaced(10)), kMaxCoverageFactor);
  EXPECT_EQ(CrossingProbability(2.0, std::vector<double>{}), 0.0);
  EXPECT_NEAR(CrossingProbability(2.0, std::vector<double>{1.0}), NormalTail(2.0), 1e-6);
  // More looks, a larger k_i.
  double previous = 2.0;
  for (int looks = 2; looks < 40; looks += 3) {
    const double k = InterimCoverageFactor(2.0, EquallySpaced(looks));
    EXPECT_GT(k, previous) << looks;
    previous = k;
  }
}

TEST(InterimLooks, NormalTail) {
  EXPECT_NEAR(NormalTail(0.0), 0.5, 1e-15);
  EXPECT_NEAR(NormalTail(2.0), 0.022750131948179195, 1e-15);  // 1 − NormalDist().cdf(2)
  EXPECT_NEAR(NormalTail(-2.0), 1.0 - 0.022750131948179195, 1e-15);
}

}  // namespace
}  // namespace hrgbench::bench
