#pragma once
// The coverage factor of an adaptive session's interim decisions (a sequence's [adaptive]).
//
// A session that may stop at any of its interim looks (after a run, or within one as its capture
// goes) decides each time a limit is proven conforming or non-conforming. Under a guarded rule
// with coverage factor k, one look at a unit whose value sits on a limit's edge takes the wrong
// side with probability 1 − Φ(k) (one-sided, normal estimate: 2.3 % at k = 2). Looking again and
// again and stopping at the first decision adds chances up. The interim looks are therefore taken
// with one larger k_i, chosen so that ALL of them together risk what one look at k risks:
// P(z_j ≥ k_i at some look j) = 1 − Φ(k); the session's last look, and the verdict it closes
// with, keep the limits' k.
//
// The looks share their data: the estimate at look j is the edge plus noise whose information
// grows with the free run so far, so the standardised estimates are z_j = W(t_j)/√t_j for a
// Brownian motion W and t_j the look's share of the plan's information (the canonical joint
// distribution of group-sequential tests, Jennison & Turnbull 2000, §3.1; taken here as the share
// of the plan's free-run seconds). That probability is computed exactly for the planned looks by
// recursive numerical integration of W's density between them (Armitage, McPherson & Rowe 1969):
// for equally spaced looks k_i is Pocock's boundary. Bonferroni (looks · (1 − Φ(k_i)) = 1 − Φ(k))
// ignores the sharing and would ask 3.55 instead of 2.93 for 120 equally spaced looks. A decaying
// wave gives more information early than late, so the true correlation of the looks is higher than
// assumed: the real risk is below the stated one.

#include <span>

namespace hrgbench::bench {

// P(W(t_j)/√t_j ≥ c for some j) for looks at information fractions `t` (strictly increasing,
// each in (0, 1]; SequenceConfig::InterimLookFractions). 0 for no looks. Cost: about
// 2e4·n^1.5 multiply-adds for n looks (0.1 s for 120 looks, 2 s for the most a sequence plans).
double CrossingProbability(double c, std::span<const double> t);

// k_i for interim looks at information fractions `t` of a rule with coverage factor `k`: the
// constant boundary they cross with probability 1 − Φ(k), within [k, kMaxCoverageFactor]
// (k itself for fewer than two looks). k must be in [kMinCoverageFactor, kMaxCoverageFactor];
// `t` as CrossingProbability's.
double InterimCoverageFactor(double k, std::span<const double> t);

// The one-sided tail of the standard normal, 1 − Φ(z).
double NormalTail(double z) noexcept;

}  // namespace hrgbench::bench
