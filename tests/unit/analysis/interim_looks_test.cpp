// The interim looks' coverage factor (analysis/interim_looks.hpp). Reference values from an
// independent implementation: Python's statistics.NormalDist().inv_cdf (Wichura's AS241), as
// inv_cdf(1 − (1 − cdf(k)) / looks).

#include "hrgbench/analysis/interim_looks.hpp"

#include <gtest/gtest.h>

#include "hrgbench/config/decision_rule.hpp"

namespace hrgbench::bench {
namespace {

TEST(InterimLooks, TheLooksTogetherRiskWhatOneLookAtKRisks) {
  EXPECT_NEAR(InterimCoverageFactor(2.0, 2), 2.277604838809457, 1e-9);
  EXPECT_NEAR(InterimCoverageFactor(2.0, 4), 2.530960494008706, 1e-9);
  EXPECT_NEAR(InterimCoverageFactor(2.0, 10), 2.8372759804564556, 1e-9);
  EXPECT_NEAR(InterimCoverageFactor(3.0, 10), 3.6425222758315154, 1e-9);
  // Bonferroni: looks × tail(k_i) = tail(k).
  for (const int looks : {2, 5, 10, 40}) {
    EXPECT_NEAR(looks * NormalTail(InterimCoverageFactor(2.0, looks)) / NormalTail(2.0), 1.0, 1e-9)
        << looks << " looks";
  }
}

TEST(InterimLooks, OneLookIsTheFileKAndNoneIsBeyondTheBound) {
  EXPECT_EQ(InterimCoverageFactor(2.0, 1), 2.0);
  EXPECT_EQ(InterimCoverageFactor(2.0, 0), 2.0);
  EXPECT_EQ(InterimCoverageFactor(2.0, -3), 2.0);
  // tail(6) ≈ 1e-9: k_i reaches the bound only for some 2e7 looks.
  EXPECT_EQ(InterimCoverageFactor(2.0, 1'000'000'000), kMaxCoverageFactor);
  EXPECT_EQ(InterimCoverageFactor(kMaxCoverageFactor, 10), kMaxCoverageFactor);
  // More looks, a larger k_i.
  double previous = 2.0;
  for (int looks = 2; looks < 100; ++looks) {
    const double k = InterimCoverageFactor(2.0, looks);
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
