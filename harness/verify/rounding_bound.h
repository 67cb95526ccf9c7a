// The rounding bound: how far a mean of replicate estimates can lie from the exact value of what
// it estimates through floating-point rounding alone.
//
// A constant integrand gives every replicate the same bits, so the standard error across
// replicates is 0 (or a few ulps) and Student's t would turn a difference of one ulp into
// "infinitely many standard errors". A difference within the rounding of the arithmetic is no
// evidence of bias, so the tests (statistics.h) take the standard error as at least the bound B:
// where the measured one is below B, they test against B, and the verdict's reason says so. That
// only ever raises a p-value; a bias beyond a few B is still found (mean 0.1 against exact
// 0.1000001 is 10^8 B away).
//
// With u = 2^-53 (one rounding: half an ulp relative to the value), A the replicates' mean of a
// sample's Σ|terms| (ReplicateResult::mean_abs), m the mean and r an exact reference:
//
//   B = u (s A + 6 |m| + |r|)
//
//   s    roundings of one per-sample estimate Σ_t f_t c_t / (p(x_t) p(y)) relative to its
//        Σ|terms|: kTermRoundings for one term, plus one per connection (the terms are summed
//        plainly) and one per importance evaluation (so is P's normaliser Σw): sample_roundings()
//        counts them from the run's counters. Of the value's arithmetic only: which paths are
//        drawn is the sampler's business and shows in the spread.
//   6    the two compensated means, the samples into a replicate and the replicates into m:
//        Neumaier's sum is within 2 roundings of the exact sum (its n u² Σ|x| term is below
//        2^-21 u A for n <= 2^32, inside the spare rounding of "one per connection"), and the
//        division by the count is one more.
//   |r|  an exact reference written in decimal is within half an ulp of its value.
//
// The bound does not cover an integrand whose own evaluation loses more than its last rounding
// (cancellation in f itself): that computed f is another function, and a verdict of "biased"
// about it is right.
#pragma once

#include <vector>

#include "estimators/estimator.h"
#include "harness/run/runner.h"

namespace pcbench {

inline constexpr double kUnitRoundoff = 0x1p-53;

// One term f c / (p(x) p(y)): f 1; p(x), p(y) and their product 3; the division and the product
// with f 2; c = 1 / (normaliser K) / P 3; P = scaled w × (1 - mix) / Σw + mix / M 6
// (estimators/resampling.cpp, resampling_step.cpp; vertex connection's c = 1 / M² / (1 / M) is 4).
inline constexpr double kTermRoundings = 15.0;
// The samples into a replicate's mean and the replicates into the run's, 3 each.
inline constexpr double kMeanRoundings = 6.0;
// An estimate read from decimal text (verify --estimates): half an ulp, one rounding.
inline constexpr double kDecimalRoundings = 1.0;

// s of a finished analytic run of the resampling family, from what it counted. Scene runs count
// other things; their paths' arithmetic is longer than this, but their replicates are never equal
// (random path throughputs), so their spread is far above any rounding.
double sample_roundings(const Counters& counters);

// u (s A + 6 |m|): the bound without a reference, for one side of a comparison; NaN when a
// replicate is not finite (there is no bound to speak of).
double rounding_bound(const std::vector<ReplicateResult>& replicates, double sample_roundings);

}  // namespace pcbench
