#pragma once
// The overlapping Allan deviation of a gyro's rate output, with its confidence interval (issue 28
// §3: angle random walk and bias instability from a zero-rate hold). Conventions of IEEE Std
// 952-1997 Annex C and IEEE Std 1431-2004 (the gyro's rate is the "frequency" y of time and
// frequency metrology, its integral, the angle, the "phase" x); the estimator, its equivalent
// degrees of freedom and the chi-squared interval are NIST SP 1065 (Riley, 2008) §5.2.4 and §5.3.
//
//   σ²(τ) = 1 / (2 (M − 2m + 1)) · Σ_{j=0}^{M−2m} (ȳ_{j+m} − ȳ_j)²,   τ = m τ0,
//
// where ȳ_j is the mean of the m rate samples from j on (every start, hence "overlapping") and M
// the number of samples. The interval is [σ² d / χ²(1 − p/2; d), σ² d / χ²(p/2; d)] for d
// equivalent degrees of freedom, which depend on the noise that dominates at τ (SP 1065 Table 5):
// the caller says which, or takes white rate noise (angle random walk), the bench's usual case at
// short τ.
//
// Units: whatever the samples are in (rad/s here), τ in seconds. Reading the coefficients
// (IEEE 952 C.1): white rate noise N (angle random walk) gives σ(τ) = N / √τ, so N = σ(1 s);
// rate random walk K gives σ(τ) = K √(τ / 3); bias instability B gives the flat floor
// σ ≈ 0.664 B. Conversion to °/√h, °/h is the reader's (60 · 180/π · N, 3600 · 180/π · B).
// Pure; allocates its result.

#include <cstddef>
#include <span>
#include <vector>

namespace hrgbench::analysis {

// The noise that dominates at the τ an interval is asked for (SP 1065 Table 5's five power laws,
// named for a gyro: the rate is "frequency").
enum class RateNoise {
  kWhiteAngle,      // white phase: readout quantisation of the angle
  kFlickerAngle,    // flicker phase
  kWhiteRate,       // white frequency: angle random walk (N)
  kFlickerRate,     // flicker frequency: bias instability (B)
  kRateRandomWalk,  // random-walk frequency: rate random walk (K)
};

struct AllanPoint {
  int m = 0;               // averaging factor
  double tau_s = 0.0;      // m · τ0
  double deviation = 0.0;  // σ(τ), the samples' unit
  double edf = 0.0;        // equivalent degrees of freedom of σ²(τ)
  double lower = 0.0;      // the interval's bounds on σ(τ) at the confidence asked for
  double upper = 0.0;
};

// Averaging factors 1, 2, 4, … (octaves) up to the largest with at least `min_differences`
// overlapping differences (M − 2m + 1 ≥ min_differences) in `samples` samples.
std::vector<int> OctaveFactors(std::size_t samples, std::size_t min_differences = 10);

// σ(τ) at each averaging factor of `m` (each in [1, M / 2]; others are skipped) of `rate`,
// sampled every `tau0_s`, with its interval at `confidence` (in (0, 1); 0.683 is the 1-σ one
// IEEE 952 plots) for the noise `dominant` at every τ. Non-finite samples make the result empty.
std::vector<AllanPoint> OverlappingAllanDeviation(std::span<const double> rate, double tau0_s,
                                                  std::span<const int> m,
                                                  RateNoise dominant = RateNoise::kWhiteRate,
                                                  double confidence = 0.683);

// SP 1065 Table 5: equivalent degrees of freedom of the overlapping Allan variance at factor m
// of M samples of the rate (the formulas count the M + 1 angle points the rate samples span).
double OverlappingAllanEdf(RateNoise noise, std::size_t samples, int m);

// The quantile of the chi-squared distribution with `dof` > 0 degrees of freedom at probability
// p in (0, 1): x with P(χ² ≤ x) = p.
double ChiSquaredQuantile(double p, double dof);

}  // namespace hrgbench::analysis
