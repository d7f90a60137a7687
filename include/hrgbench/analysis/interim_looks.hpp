#pragma once
// The coverage factor of an adaptive session's interim decisions (a sequence's [adaptive]).
//
// A session that may stop after any of `looks` runs before its last decides each time a limit is
// proven conforming or non-conforming. Under a guarded rule with coverage factor k, one look at a
// unit whose value sits on a limit's edge takes the wrong side with probability 1 − Φ(k)
// (one-sided, normal estimate: 2.3 % at k = 2). Looking after every run and stopping at the first
// decision adds those chances up. The interim looks are therefore taken with k_i such that the
// `looks` of them together risk no more than one look at k (Bonferroni: `looks` · (1 − Φ(k_i)) = 1
// − Φ(k)); the session's last look, and the verdict it closes with, keep the limits' k. So an
// adaptive session's chance of a wrong interim decision is at most that of its final one, and in
// practice far less: successive looks share most of their data, which Bonferroni does not credit.
// Pure; no allocation.

namespace hrgbench::bench {

// k_i for `looks` interim looks of a rule with coverage factor `k` (k itself for looks <= 1),
// within [k, kMaxCoverageFactor]. k must be in [kMinCoverageFactor, kMaxCoverageFactor].
double InterimCoverageFactor(double k, int looks) noexcept;

// The one-sided tail of the standard normal, 1 − Φ(z).
double NormalTail(double z) noexcept;

}  // namespace hrgbench::bench
