// Figures computed from a run's replicates: aggregates (bias, standard error, RMSE, relative MSE,
// efficiency) and the test of E[estimate] = reference, with one false-alarm budget per suite.
//
// Every standard error and test uses the spread *across replicates* (docs/reference/INTERFACE.md):
// replicates are independent even where the samples within one share a pool.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "harness/run/runner.h"
#include "integrands/integrand.h"

namespace pcbench {

inline constexpr double kDefaultAlpha = 0.01;  // family-wise, per suite
inline constexpr double kPower = 0.8;          // for the minimum detectable bias

// NaN marks a figure that is undefined (e.g. the bias without a reference).
// One point of a run's convergence series: the replicates' running estimates after `samples`
// samples each.
struct SeriesPoint {
  std::uint64_t samples = 0;
  double mean = 0.0;
  double stderr_of_mean = 0.0;
  double bias = 0.0;         // NaN without a reference
  double rmse = 0.0;         // of one replicate's running estimate; NaN without a reference
  double cpu_seconds = 0.0;  // per replicate, mean over replicates
  double seconds = 0.0;      // wall, per replicate, mean over replicates
};

struct Aggregates {
  double mean = 0.0;
  double stderr_of_mean = 0.0;  // across replicates
  double bias = 0.0;
  double rmse = 0.0;                // of one replicate's estimate against the reference
  double rel_mse = 0.0;             // mse / reference²
  double seconds_per_sample = 0.0;  // thread CPU seconds per camera sample
  double efficiency = 0.0;          // 1 / (per-sample variance × seconds per sample)
  double mean_abs = 0.0;            // estimate of ∫∫ |f|, the scale of "a small bias"
  // 95% interval of the efficiency from the chi-square interval of the variance across R
  // replicates (the time per sample is measured far more precisely than the variance).
  double efficiency_low = 0.0;
  double efficiency_high = 0.0;
  std::vector<SeriesPoint> series = {};
  // Least-squares slope of log RMSE against log samples over the series: -1/2 where the
  // variance is finite and the estimator unbiased (reported, not assumed). NaN without a
  // reference or with fewer than 3 points.
  double rmse_slope = std::numeric_limits<double>::quiet_NaN();
};

Aggregates aggregate(const std::vector<ReplicateResult>& replicates, const Reference& reference,
                     std::uint64_t samples_per_replicate);

// The convergence series of a run (its replicates' checkpoints) and its log-log RMSE slope.
std::vector<SeriesPoint> convergence_series(const std::vector<ReplicateResult>& replicates,
                                            const Reference& reference);
double rmse_slope(const std::vector<SeriesPoint>& series);

// The test name of a scene's block pyramid (harness/verify/block_verdicts.h) in verdicts and
// reports.
inline constexpr const char* kBlockPyramidTest = "block-pyramid";

struct Verdict {
  std::string test;  // "student_t", "welch", "none"
  double statistic = 0.0;
  double dof = 0.0;
  double p_value = 1.0;  // raw, two-sided
  double p_adjusted = 1.0;
  double alpha = kDefaultAlpha;  // the family-wise threshold p_adjusted is compared with
  std::string result;            // consistent | biased | inconclusive
  std::string reason;
  std::string expect;
  double min_detectable_bias = 0.0;              // at 80% power with the Bonferroni share alpha / m
  double min_detectable_rel_bias = 0.0;          // NaN where the reference is 0 or absent
  double min_detectable_bias_vs_mean_abs = 0.0;  // relative to ∫∫ |f|: comparable across rows
  bool tested = false;                           // counts in the family
  double test_stderr = 0.0;                      // the test's denominator
  // The rounding bound (harness/verify/rounding_bound.h) and the standard error the estimates gave:
  // test_stderr is the larger (0 and 0 without a bound: the untested, the tile tests).
  double rounding_bound = 0.0;
  double measured_stderr = 0.0;
  double reference_value = 0.0;
  double mean_abs = 0.0;
};

// What the samples say about whether Student's t applies at all.
struct SampleDiagnostics {
  // Generalized-Pareto shape k̂ of the |estimate| tail, averaged over the replicates (each fits
  // its own largest values; NaN where no replicate had a tail to fit). k̂ > 1/2: the variance
  // may be infinite.
  double tail_shape = std::numeric_limits<double>::quiet_NaN();
  std::size_t tail_size = 0;  // exceedances per replicate fit (the first replicate's)
  // Median over replicates of the largest sample's share of Σ x². With a finite variance it
  // vanishes as n grows (measured: below 0.01 at 10^5 samples even for k = 0.3 or clustered
  // values); with an infinite one the largest sample keeps a share of order 1 (0.3 to 0.6
  // measured for k = 0.75, at 2·10^4 samples as at 10^5).
  double largest_share = std::numeric_limits<double>::quiet_NaN();
  std::uint64_t nonzero = 0;  // non-zero samples over all replicates
  // The smallest replicate's effective sample size (Kish): the t test needs replicate means
  // that are roughly normal, which a handful of dominant samples are not.
  double min_effective_samples = std::numeric_limits<double>::quiet_NaN();
};

// Below this many effective samples in some replicate a run is not tested: such a replicate's
// mean is far from normal (a Poisson-like count of hits of mean 10 still has skewness 0.3), and
// one with no hit at all has variance 0, which would make Student's t confidently wrong.
inline constexpr double kMinEffectiveSamples = 10.0;
// A heavy tail (k̂ > 1/2) counts as infinite variance only when the largest sample also holds
// more than this share of Σ x²: the GPD fit alone misreads bounded but clustered samples (sums
// of a few rare, similar connections; ratios with a random normaliser) as heavy-tailed, with
// k̂ up to 2 measured on such bounded estimates.
inline constexpr double kDominantShare = 0.1;

SampleDiagnostics diagnose_samples(const std::vector<ReplicateResult>& replicates);

// Why Student's t must not be trusted on these samples, or nothing when it may.
std::optional<std::string> untestable_reason(const SampleDiagnostics& diagnostics);

// A verdict for a run that is not tested, and why (no reference; a declared infinite variance).
Verdict untested_verdict(std::string reason, std::string expect);

// The raw test of replicate estimates against their reference (no multiplicity correction
// yet), Student's t or Welch's. Where its standard error is below the rounding bound
// (harness/verify/rounding_bound.h; `sample_roundings` is its s for these estimates) it tests
// against the bound instead.
Verdict test_against_reference(const std::vector<ReplicateResult>& replicates,
                               const Reference& reference, std::string expect,
                               double sample_roundings);
// The same for a finished analytic run: its replicates and reference, s from its counters.
Verdict test_against_reference(const RunResult& run, std::string expect);

// Holm–Bonferroni over the tested verdicts: fills p_adjusted, alpha, result, reason and the
// minimum detectable bias (which needs the family size m). Verdicts may be null (failed runs).
void decide_family(std::vector<Verdict*>& verdicts, double alpha);

// Two-sided p-value of Student's t with `dof` degrees of freedom.
double student_t_p_value(double t, double dof);

// Welch's test of equal means of two independent estimates, each given by its mean, the variance
// of that mean (its squared standard error) and the degrees of freedom of that variance
// (infinity for a value whose uncertainty is known exactly).
struct TwoSampleTest {
  double statistic = 0.0;  // (mean_a - mean_b) / stderr_of_difference; ±inf if it is 0
  double dof = 0.0;        // Welch–Satterthwaite
  double p_value = 1.0;    // two-sided
  double mean_a = 0.0;
  double mean_b = 0.0;
  double stderr_a = 0.0;  // standard error of mean_a
  double stderr_b = 0.0;
  double stderr_of_difference = 0.0;  // sqrt(stderr_a² + stderr_b²), or the rounding bound
  double rounding_bound = 0.0;        // 0 unless with_rounding_floor() gave one
};
TwoSampleTest welch_test(double mean_a, double variance_of_mean_a, double dof_a, double mean_b,
                         double variance_of_mean_b, double dof_b);

// Welch's two-sample t-test on two sets of independent replicate estimates (each of size >= 2;
// NaN figures otherwise). When neither sample varies the test is exact: p = 1 for equal means,
// 0 otherwise, and dof is (n_a - 1) + (n_b - 1).
TwoSampleTest welch_two_sample(std::span<const double> a, std::span<const double> b);

// The paired t-test on replicate pairs (a[r], b[r]) whose pairs are independent of each other
// but whose two members may be correlated (runs on shared random streams): Student's one-sample
// test of the differences a[r] - b[r] against 0, dof n - 1. stderr_of_difference is the
// differences' standard error, which is below Welch's where the members correlate positively;
// stderr_a and stderr_b are each side's own. Where the differences do not vary the test is
// exact (p = 1 for equal means, 0 otherwise). Throws std::invalid_argument for spans of
// different lengths; NaN figures for fewer than 2 pairs.
TwoSampleTest paired_t_test(std::span<const double> a, std::span<const double> b);

// The test against a standard error of at least `bound`, the sum of both sides' rounding bounds
// (harness/verify/rounding_bound.h): where stderr_of_difference is below it, the statistic and
// p-value are those against the bound (dof unchanged).
TwoSampleTest with_rounding_floor(TwoSampleTest test, double bound);

// The raw verdict of a two-sample test (before the family's correction), so that it can join a
// family with the runs' tests; the test's standard error gives its minimum detectable difference.
Verdict two_sample_verdict(const TwoSampleTest& test, std::string expect);

// The median; NaN when some value is (an unknown detectable bias must not read as a small one)
// or there are none.
double median_or_nan(std::vector<double> values);

// Holm's step-down adjusted p-values, in the order of `p_values`:
// p_adj(i) = max over j <= i of min(1, (m - j + 1) p_(j)) with p_(1) <= ... <= p_(m).
std::vector<double> holm_adjusted(std::span<const double> p_values);

// The weighted Holm procedure (Holm 1979, with weights w_i > 0 summing to 1): with the tests
// ordered by p_i / w_i, p_adj(i) = max over j <= i of min(1, p_(j) / w_(j) × Σ_{k >= j} w_(k)).
// Rejecting p_adj <= alpha holds the family-wise error at alpha, and a test of weight w is held
// to alpha × w at the first step. Equal weights give holm_adjusted. Throws std::invalid_argument
// for spans of different lengths or a weight that is not positive.
std::vector<double> weighted_holm_adjusted(std::span<const double> p_values,
                                           std::span<const double> weights);

// t_{1 - share/2, dof} + t_{power, dof}: times a test's standard error, the smallest difference a
// two-sided test at level `share` detects with probability `power` (normal-theory approximation
// with Student quantiles).
double detectable_multiplier(double share, double dof, double power = kPower);

// Power of the two-sided t test at level `share` (critical value c = t_{1-share/2, dof}) against
// a bias of `ncp` true standard errors: P(|T'| > c) for T' noncentral t with `dof` and
// noncentrality ncp. Exact for normal replicate estimates and a fixed bias.
double noncentral_t_power(double ncp, double dof, double share);

// The same test when the bias is `shift` *estimated* standard errors of the very sample tested
// (as a bias of k × that sample's reported minimum detectable bias is): the statistic is then
// the unbiased one plus exactly `shift`, so the power is P(T > c - shift) + P(T < -c - shift) for
// T Student's t with `dof`. At shift = detectable_multiplier(share, dof, power) it is `power`
// (less the far tail's ~0), which is what the minimum detectable bias promises.
double shifted_t_power(double shift, double dof, double share);

// Wilson score interval of a binomial proportion at two-sided confidence `confidence` (0.95 for
// 95%). {0, 1} when trials is 0.
struct ProportionInterval {
  double low = 0.0;
  double high = 1.0;
};
ProportionInterval wilson_interval(std::uint64_t successes, std::uint64_t trials,
                                   double confidence);

}  // namespace pcbench
