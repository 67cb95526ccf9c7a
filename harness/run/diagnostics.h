// Diagnostics of a sample, separate from the verdict on its mean: how heavy its upper tail is
// (the generalized-Pareto shape k̂ of PSIS), whether values meant to be Uniform(0, 1) are (a
// one-sample Kolmogorov–Smirnov test), and an exact binomial test for counts (e.g. how many runs
// of a family rejected, against the rate alpha).
//
// Self-contained: nothing here depends on runs, suites or reports.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace pcbench {

// ---------------------------------------------------------------------------------------------
// Tail shape

// A generalized Pareto distribution with shape k has a finite variance iff k < 1/2 (and a finite
// mean iff k < 1), so k̂ > 0.5 says the sample's variance may be infinite: its standard errors,
// and any test built on them, are then not to be trusted however many samples there are.
inline constexpr double kInfiniteVarianceShape = 0.5;

// A generalized Pareto fit to the exceedances over a threshold: P(X - threshold > y | X >
// threshold) = (1 + k y / sigma)^(-1/k). NaN (and tail_size 0) when there was nothing to fit.
struct TailShape {
  double k = std::numeric_limits<double>::quiet_NaN();             // with PSIS's prior adjustment
  double k_unadjusted = std::numeric_limits<double>::quiet_NaN();  // Zhang & Stephens's estimate
  double sigma = std::numeric_limits<double>::quiet_NaN();         // scale, from k_unadjusted
  std::size_t tail_size = 0;  // M, the number of exceedances fitted
  double threshold = std::numeric_limits<double>::quiet_NaN();  // the (M+1)-th largest value
};

// PSIS's tail size for a sample of `total_count` values: M = ceil(min(0.2 n, 3 sqrt(n))), at most
// n - 1 (Vehtari, Simpson, Gelman, Yao & Gabry, "Pareto smoothed importance sampling", JMLR 25
// (2024); loo's psis uses the same, rounded up). A
// caller that keeps only the largest values needs pareto_tail_size(n) + 1 of them: the M
// exceedances and the threshold.
std::size_t pareto_tail_size(std::uint64_t total_count);

// Generalized-Pareto shape k̂ of the upper tail of a sample of `total_count` values, of which
// `largest_descending` holds the largest, largest first (the whole sample, or fewer). Fits the
// M = min(pareto_tail_size(total_count), largest_descending.size() - 1) largest values' excesses
// over the (M+1)-th largest with Zhang & Stephens's estimator ("A new and efficient estimation
// method for the generalized Pareto distribution", Technometrics 51 (2009)) as PSIS does.
//
// Excesses of exactly 0 (ties with the threshold, e.g. a sample with repeated values) carry no
// information on the shape and are left out. Returns the NaN TailShape when fewer than 5 excesses
// are left: a constant sample, total_count < 21 (M < 5), or fewer than 6 largest values given.
// Throws std::invalid_argument if a value is not finite, the values are not in descending order,
// or there are more of them than total_count.
TailShape pareto_tail_shape(std::span<const double> largest_descending, std::uint64_t total_count);

// ---------------------------------------------------------------------------------------------
// Kolmogorov–Smirnov

struct KsResult {
  double statistic = 0.0;  // D_n = sup |F_n(x) - x|
  double p_value = 1.0;    // P(D_n >= statistic) for n uniform values
  std::size_t n = 0;
};

// Two-sided one-sample Kolmogorov–Smirnov test of `values` against Uniform(0, 1).
// Throws std::invalid_argument if `values` is empty or holds a value outside [0, 1] or NaN.
KsResult ks_uniform(std::vector<double> values);

// P(D_n >= d) for the two-sided statistic D_n of n independent Uniform(0, 1) values.
//   n <= kKsExactMaxN: exact. Where p >= 1e-5, 1 - P(D_n < d) by Marsaglia, Tsang & Wang
//     ("Evaluating Kolmogorov's distribution", J. Stat. Softw. 8(18), 2003; absolute error
//     ~1e-14). In the upper tail, where that difference would lose its digits to cancellation,
//     twice Smirnov's exact one-sided probability (Birnbaum & Tingey 1951): P(D_n >= d) itself
//     for d >= 1/2, and below it too large by P(D+ >= d and D- >= d), asymptotically a relative
//     (p/2)^3 (Miller 1956); it keeps its relative precision down to underflow.
//   n > kKsExactMaxN: Kolmogorov's limit Q(lambda) = 2 sum (-1)^(j-1) exp(-2 j^2 lambda^2) with
//     Vrbik's finite-n correction lambda = sqrt(n) d + 1/(6 sqrt(n)) + (sqrt(n) d - 1)/(4n)
//     ("Small-sample corrections to Kolmogorov–Smirnov test statistic", Pioneer J. Theor. Appl.
//     Stat. 15, 2018). Against the exact value at n = 1000 its relative error is below 0.6% for
//     p >= 1e-4 and 3% for p >= 1e-8, shrinking as 1/n; Stephens's better-known (sqrt(n) + 0.12 +
//     0.11/sqrt(n)) d is 2% off at p = 1e-4. The exact method's cost grows as (n d)^3 log n: ~20 ms
//     at n = 1000.
// NaN if d is NaN or n is 0.
inline constexpr std::uint64_t kKsExactMaxN = 1000;
double ks_p_value(double d, std::uint64_t n);

// ---------------------------------------------------------------------------------------------
// Binomial

// Exact two-sided p-value of `successes` in `trials` Bernoulli(p) trials: the total probability
// of the outcomes no more likely than the observed one, with R's relative tolerance 1 + 1e-7 on
// "no more likely" so that rounding does not split ties (R's binom.test, scipy's binomtest).
// 1 when trials is 0. Throws std::invalid_argument if successes > trials, trials > 2^53 (not
// exact as a double) or p is not in [0, 1].
double binomial_test_p_value(std::uint64_t successes, std::uint64_t trials, double p);

// One-sided: P(X >= successes) for X ~ Binomial(trials, p), the p-value of "more successes than
// p allows" (1 for 0 successes). Where fewer successes than p are expected by design (a
// conservative test's false alarms), only this side is a failure. Throws as
// binomial_test_p_value does.
double binomial_upper_p_value(std::uint64_t successes, std::uint64_t trials, double p);

}  // namespace pcbench
