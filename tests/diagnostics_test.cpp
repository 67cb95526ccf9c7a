#include "harness/run/diagnostics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <stdexcept>
#include <vector>

#include "base/rng.h"

namespace pcbench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------------------------------------
// Tail shape

constexpr std::uint64_t kTailSampleSize = 200000;

// n values drawn by `draw` from a fixed-seed stream.
std::vector<double> sample(std::uint64_t seed, std::uint64_t n,
                           const std::function<double(RandomStream&)>& draw) {
  RandomStream rng({.key = seed});
  std::vector<double> values(n);
  for (double& v : values) v = draw(rng);
  return values;
}

// The `count` largest of `values`, largest first.
std::vector<double> largest(std::vector<double> values, std::size_t count) {
  count = std::min(count, values.size());
  std::partial_sort(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(count),
                    values.end(), std::greater<>());
  values.resize(count);
  return values;
}

// The fit to the tail PSIS uses: the pareto_tail_size(n) + 1 largest values.
TailShape fit_tail(const std::vector<double>& values) {
  const std::vector<double> top = largest(values, pareto_tail_size(values.size()) + 1);
  return pareto_tail_shape(top, values.size());
}

// GPD(k, sigma = 1) by inversion; 1 - u is in (0, 1], so every draw is finite.
double gpd(RandomStream& rng, double k) {
  return (std::pow(1.0 - rng.uniform(), -k) - 1.0) / k;
}

// |U1 - U2|^-a: P(X > x) = P(|U1 - U2| < x^(-1/a)) ~ 2 x^(-1/a), a Pareto tail with k = a. The
// catalog's singular integrands have this form.
double singular(RandomStream& rng, double a) {
  return std::pow(std::fabs(rng.uniform() - rng.uniform()), -a);
}

// The asymptotic standard deviation of the GPD shape's MLE from M excesses, (1 + k) / sqrt(M)
// (Smith 1985; Zhang & Stephens's estimator is asymptotically as efficient). 5 of them: a
// tolerance that a correct estimator misses with probability ~6e-7 (the seeds are fixed anyway),
// while a wrong tail size, sign convention or threshold shifts k̂ by far more.
double shape_tolerance(double k, std::size_t m) {
  return 5.0 * (1.0 + k) / std::sqrt(static_cast<double>(m));
}

TEST(DiagnosticsParetoTail, TailSizeIsPsisRule) {
  EXPECT_EQ(pareto_tail_size(0), 0u);
  EXPECT_EQ(pareto_tail_size(1), 0u);
  EXPECT_EQ(pareto_tail_size(2), 1u);                                // ceil(0.4), at most n - 1
  EXPECT_EQ(pareto_tail_size(10), 2u);                               // 0.2 n
  EXPECT_EQ(pareto_tail_size(100), 20u);                             // 0.2 n = 20 < 3 sqrt(n) = 30
  EXPECT_EQ(pareto_tail_size(225), 45u);                             // both 45
  EXPECT_EQ(pareto_tail_size(kTailSampleSize), 1342u);               // ceil(3 sqrt(2e5) = 1341.6)
  EXPECT_EQ(pareto_tail_size(10'000'000), 9487u);                    // ceil(9486.8)
  EXPECT_EQ(pareto_tail_size(std::uint64_t{1} << 62), 6442450944u);  // 3 * 2^31
}

TEST(DiagnosticsParetoTail, RecoversGpdShapeAndScale) {
  for (const double k : {0.3, 0.75}) {
    SCOPED_TRACE(k);
    const std::vector<double> values =
        sample(11, kTailSampleSize, [k](RandomStream& rng) { return gpd(rng, k); });
    const TailShape fit = fit_tail(values);
    ASSERT_EQ(fit.tail_size, pareto_tail_size(kTailSampleSize));
    EXPECT_NEAR(fit.k, k, shape_tolerance(k, fit.tail_size));
    // Excesses of GPD(k, 1) over u are GPD(k, 1 + k u): the same shape, a known scale. The
    // scale's MLE has relative standard deviation sqrt(2 (1 + k) / M); 5 of them.
    const double tolerance = 5.0 * std::sqrt(2.0 * (1.0 + k) / static_cast<double>(fit.tail_size));
    EXPECT_NEAR(fit.sigma / (1.0 + k * fit.threshold), 1.0, tolerance);
  }
}

TEST(DiagnosticsParetoTail, ExponentialTailHasShapeZero) {
  const std::vector<double> values =
      sample(12, kTailSampleSize, [](RandomStream& rng) { return -std::log1p(-rng.uniform()); });
  const TailShape fit = fit_tail(values);
  EXPECT_NEAR(fit.k, 0.0, shape_tolerance(0.0, fit.tail_size));
}

TEST(DiagnosticsParetoTail, UniformHasNegativeShape) {
  // Excesses of U(0, 1) over u are U(0, 1 - u): a GPD with k = -1 (where the MLE's asymptotics
  // no longer hold, so only the sign is asserted; k̂ is about -0.95 here).
  const std::vector<double> values =
      sample(13, kTailSampleSize, [](RandomStream& rng) { return rng.uniform(); });
  const TailShape fit = fit_tail(values);
  EXPECT_LT(fit.k, 0.0);
}

TEST(DiagnosticsParetoTail, SeparatesTheCatalogsFiniteAndInfiniteVariance) {
  // The two singular kernels the catalog declares: |U1-U2|^-0.3 has a finite variance (k = 0.3),
  // |U1-U2|^-0.75 does not (k = 0.75). Each is 5 standard deviations from the line.
  const TailShape finite =
      fit_tail(sample(14, kTailSampleSize, [](RandomStream& rng) { return singular(rng, 0.3); }));
  const TailShape infinite =
      fit_tail(sample(15, kTailSampleSize, [](RandomStream& rng) { return singular(rng, 0.75); }));
  EXPECT_LT(finite.k, kInfiniteVarianceShape);
  EXPECT_GT(infinite.k, kInfiniteVarianceShape);
  EXPECT_NEAR(finite.k, 0.3, shape_tolerance(0.3, finite.tail_size));
  EXPECT_NEAR(infinite.k, 0.75, shape_tolerance(0.75, infinite.tail_size));
}

TEST(DiagnosticsParetoTail, ThresholdAndTailSizeFollowTheValuesGiven) {
  const std::vector<double> values =
      sample(16, 10000, [](RandomStream& rng) { return gpd(rng, 0.5); });
  const std::size_t m = pareto_tail_size(values.size());  // 300
  const std::vector<double> top = largest(values, m + 1);
  const TailShape full = pareto_tail_shape(top, values.size());
  EXPECT_EQ(full.tail_size, m);
  EXPECT_EQ(full.threshold, top[m]);
  // Extra values below the threshold change nothing.
  const TailShape more = pareto_tail_shape(largest(values, 2 * m), values.size());
  EXPECT_EQ(more.k, full.k);
  EXPECT_EQ(more.threshold, full.threshold);
  // Fewer values than the rule asks for (the tally keeps 16): the tail is what there is.
  const TailShape few = pareto_tail_shape(std::span(top).first(16), values.size());
  EXPECT_EQ(few.tail_size, 15u);
  EXPECT_EQ(few.threshold, top[15]);
  EXPECT_TRUE(std::isfinite(few.k));
}

TEST(DiagnosticsParetoTail, PriorAdjustmentPullsTowardsOneHalf) {
  const std::vector<double> values =
      sample(17, 10000, [](RandomStream& rng) { return gpd(rng, 0.2); });
  const TailShape fit = fit_tail(values);
  const double m = static_cast<double>(fit.tail_size);
  EXPECT_NEAR(fit.k - 0.5, m * (fit.k_unadjusted - 0.5) / (m + 10.0), 1e-14);
}

TEST(DiagnosticsParetoTail, ScaleInvariant) {
  const std::vector<double> values =
      sample(18, 10000, [](RandomStream& rng) { return gpd(rng, 0.4); });
  std::vector<double> scaled = values;
  for (double& v : scaled) v *= 1024.0;  // exact, so the fit sees the same values times 2^10
  const TailShape a = fit_tail(values);
  const TailShape b = fit_tail(scaled);
  EXPECT_NEAR(b.k, a.k, 1e-12);
  EXPECT_NEAR(b.sigma / a.sigma, 1024.0, 1e-9);
  EXPECT_EQ(b.threshold, 1024.0 * a.threshold);
}

TEST(DiagnosticsParetoTail, NothingToFitGivesNaN) {
  // A constant sample: every excess is 0.
  const std::vector<double> constant(1000, 3.5);
  const TailShape flat = fit_tail(constant);
  EXPECT_TRUE(std::isnan(flat.k));
  EXPECT_TRUE(std::isnan(flat.sigma));
  EXPECT_EQ(flat.tail_size, 0u);
  // Too small a sample (M = 2 of 6; M >= 5 needs n >= 21), too few values given, nothing given.
  const std::vector<double> six = {6, 5, 4, 3, 2, 1};
  EXPECT_TRUE(std::isnan(pareto_tail_shape(six, 6).k));
  const std::vector<double> twenty =
      sample(19, 20, [](RandomStream& rng) { return gpd(rng, 0.5); });
  EXPECT_TRUE(std::isnan(fit_tail(twenty).k));
  const std::vector<double> twenty_one =
      sample(19, 21, [](RandomStream& rng) { return gpd(rng, 0.5); });
  EXPECT_EQ(fit_tail(twenty_one).tail_size, 5u);
  EXPECT_TRUE(std::isnan(pareto_tail_shape(std::span(six).first(5), 1000).k));
  EXPECT_TRUE(std::isnan(pareto_tail_shape({}, 1000).k));
  // Ties with the threshold are left out: 4 distinct excesses are too few, 5 are enough.
  const std::vector<double> ties = {9, 8, 7, 6, 1, 1, 1, 1, 1, 1, 1};
  EXPECT_TRUE(std::isnan(pareto_tail_shape(std::span(ties).first(10), 1000).k));
  const std::vector<double> five = {9, 8, 7, 6, 5, 1, 1, 1, 1, 1, 1};
  const TailShape fitted = pareto_tail_shape(five, 1000);
  EXPECT_EQ(fitted.tail_size, 5u);
  EXPECT_EQ(fitted.threshold, 1.0);
  EXPECT_TRUE(std::isfinite(fitted.k));
}

TEST(DiagnosticsParetoTail, RejectsBadInput) {
  const std::vector<double> ascending = {1, 2, 3, 4, 5, 6, 7};
  EXPECT_THROW(pareto_tail_shape(ascending, 100), std::invalid_argument);
  const std::vector<double> with_nan = {7, 6, kNaN, 4, 3, 2, 1};
  EXPECT_THROW(pareto_tail_shape(with_nan, 100), std::invalid_argument);
  const std::vector<double> with_inf = {std::numeric_limits<double>::infinity(), 6, 5, 4, 3, 2, 1};
  EXPECT_THROW(pareto_tail_shape(with_inf, 100), std::invalid_argument);
  const std::vector<double> seven = {7, 6, 5, 4, 3, 2, 1};
  EXPECT_THROW(pareto_tail_shape(seven, 6), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Kolmogorov–Smirnov

// P(D_n >= d) by Steck's determinant (Steck 1971, "Rectangle probabilities for uniform order
// statistics"): P(a_i < U_(i) < b_i for all i) = n! det M, M_ij = (b_i - a_j)_+^(j-i+1) /
// (j-i+1)! (0 where j < i - 1), with D_n < d iff i/n - d < U_(i) < (i-1)/n + d. A method
// independent of the one under test; it cancels badly, so only for small n.
double steck_p_value(double d, int n) {
  std::vector<long double> a(static_cast<std::size_t>(n)), b(a.size());
  for (int i = 1; i <= n; ++i) {
    a[static_cast<std::size_t>(i - 1)] = std::max(0.0L, static_cast<long double>(i) / n - d);
    b[static_cast<std::size_t>(i - 1)] = std::min(1.0L, static_cast<long double>(i - 1) / n + d);
  }
  std::vector<std::vector<long double>> m(a.size(), std::vector<long double>(a.size(), 0.0L));
  for (int i = 0; i < n; ++i) {
    for (int j = std::max(0, i - 1); j < n; ++j) {
      const int e = j - i + 1;
      const long double x =
          std::max(0.0L, b[static_cast<std::size_t>(i)] - a[static_cast<std::size_t>(j)]);
      m[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] =
          std::pow(x, static_cast<long double>(e)) / std::tgamma(static_cast<long double>(e + 1));
    }
  }
  // Determinant by Gaussian elimination with partial pivoting, times n!.
  long double det = std::tgamma(static_cast<long double>(n + 1));
  for (std::size_t c = 0; c < m.size(); ++c) {
    std::size_t pivot = c;
    for (std::size_t r = c + 1; r < m.size(); ++r) {
      if (std::fabs(m[r][c]) > std::fabs(m[pivot][c])) pivot = r;
    }
    if (m[pivot][c] == 0.0L) return 1.0;
    if (pivot != c) {
      std::swap(m[pivot], m[c]);
      det = -det;
    }
    det *= m[c][c];
    for (std::size_t r = c + 1; r < m.size(); ++r) {
      const long double f = m[r][c] / m[c][c];
      for (std::size_t j = c; j < m.size(); ++j) m[r][j] -= f * m[c][j];
    }
  }
  return static_cast<double>(1.0L - det);
}

TEST(DiagnosticsKs, StatisticOfAHandMadeSample) {
  // Sorted 0.1, 0.4, 0.7 (n = 3): i/n - u_(i) = 0.2333, 0.2667, 0.3; u_(i) - (i-1)/n = 0.1,
  // 0.0667, 0.0333. D = 0.3, from the last point's step up to 1.
  const KsResult r = ks_uniform({0.7, 0.1, 0.4});
  EXPECT_EQ(r.n, 3u);
  EXPECT_NEAR(r.statistic, 0.3, 1e-15);
  EXPECT_EQ(r.p_value, ks_p_value(r.statistic, 3));
  // One value: D = max(u, 1 - u).
  EXPECT_NEAR(ks_uniform({0.2}).statistic, 0.8, 1e-15);
  EXPECT_NEAR(ks_uniform({0.5}).statistic, 0.5, 1e-15);
  // Values above the diagonal: 0.9, 0.95 give D = u_(1) - 0 = 0.9.
  EXPECT_NEAR(ks_uniform({0.95, 0.9}).statistic, 0.9, 1e-15);
}

TEST(DiagnosticsKs, ClosedFormsForOneAndTwoValues) {
  // n = 1: D = max(U, 1 - U) >= d iff U >= d or U <= 1 - d: 2 (1 - d) for d >= 1/2.
  for (const double d : {0.5, 0.6, 0.75, 0.9, 0.999}) {
    EXPECT_NEAR(ks_p_value(d, 1), 2.0 * (1.0 - d), 1e-14) << d;
  }
  EXPECT_EQ(ks_p_value(0.3, 1), 1.0);
  // n = 2: D < d iff 1/2 - d < U(1) < d and 1 - d < U(2) < 1/2 + d. For 1/4 <= d <= 1/2 the two
  // intervals (each 2d - 1/2 long) are disjoint and ordered: P(D < d) = 2! (2d - 1/2)^2. For
  // d >= 1/2 they are (0, d) and (1 - d, 1), overlapping on 2d - 1 with half of that square out of
  // order: P(D < d) = 2 (d^2 - (2d - 1)^2 / 2), so P(D >= d) = 2 (1 - d)^2.
  for (const double d : {0.26, 0.3, 0.4, 0.45, 0.5}) {
    EXPECT_NEAR(ks_p_value(d, 2), 1.0 - 2.0 * (2.0 * d - 0.5) * (2.0 * d - 0.5), 1e-14) << d;
  }
  for (const double d : {0.55, 0.6, 0.75, 0.9}) {
    EXPECT_NEAR(ks_p_value(d, 2), 2.0 * (1.0 - d) * (1.0 - d), 1e-14) << d;
  }
  EXPECT_EQ(ks_p_value(0.25, 2), 1.0);  // D_2 >= 1/4 always
}

TEST(DiagnosticsKs, ExtremeTailKeepsRelativePrecision) {
  // For d >= 1 - 1/n, D_n >= d iff every U_i < 1 - d or every U_i > d (disjoint events):
  // P = 2 (1 - d)^n, however small; 1 - P(D < d) would round to 0.
  const struct {
    std::uint64_t n;
    double d;
  } cases[] = {{5, 0.85}, {20, 0.97}, {40, 0.98}, {100, 0.995}};  // down to 2e-230
  for (const auto& c : cases) {
    const double expected = 2.0 * std::pow(1.0 - c.d, static_cast<double>(c.n));
    EXPECT_NEAR(ks_p_value(c.d, c.n) / expected, 1.0, 1e-11) << c.n << " " << c.d;
  }
}

TEST(DiagnosticsKs, MatchesSteckDeterminant) {
  for (int n = 3; n <= 12; ++n) {
    for (double d = 0.5 / n + 0.01; d < 1.0; d += 0.03) {
      const double expected = steck_p_value(d, n);
      EXPECT_NEAR(ks_p_value(d, static_cast<std::uint64_t>(n)), expected, 1e-12 + 1e-9 * expected)
          << "n = " << n << ", d = " << d;
    }
  }
}

TEST(DiagnosticsKs, MatchesHighPrecisionReferences) {
  // Steck's determinant in 80-digit arithmetic (Python mpmath 1.3), at the double nearest d.
  // Rows with p near 0.05 and 0.01 are Miller's (1956) tabulated critical values.
  const struct {
    std::uint64_t n;
    double d;
    double p;
  } cases[] = {
      {10, 0.2, 0.74871903999999989},      {10, 0.40925, 0.049996452334258978},
      {10, 0.48893, 0.010000371410091987}, {50, 0.1, 0.6623112704658185},
      {50, 0.2, 0.031438777769534493},     {50, 0.3, 0.00017353260202718066},
      {100, 0.05, 0.95321597106357248},    {100, 0.13581, 0.045334713646165932},
      {100, 0.2, 0.00055519273280280968},  {100, 0.25, 5.4088717764348473e-6},
  };
  for (const auto& c : cases) {
    EXPECT_NEAR(ks_p_value(c.d, c.n) / c.p, 1.0, 1e-10) << c.n << " " << c.d;
  }
}

TEST(DiagnosticsKs, AsymptoticLimit) {
  // At n = 10^12 the finite-n correction is ~1e-7: P(sqrt(n) D > lambda) is Kolmogorov's limit,
  // whose tabulated 5% and 1% points are 1.3581 and 1.6276 (rounded: Q = 0.0499996, 0.0100015).
  const double root = 1e6;
  EXPECT_NEAR(ks_p_value(1.3581 / root, 1'000'000'000'000), 0.05, 1e-5);
  EXPECT_NEAR(ks_p_value(1.6276 / root, 1'000'000'000'000), 0.01, 1e-5);
  // The limit's series in both of its forms (switching at lambda = 1.18) against closed values:
  // Q(1) and Q(0.5) from the series in 30-digit arithmetic (mpmath).
  EXPECT_NEAR(ks_p_value(1.0 / root, 1'000'000'000'000), 0.2699996716773546, 1e-6);
  EXPECT_NEAR(ks_p_value(0.5 / root, 1'000'000'000'000), 0.9639452436648752, 1e-6);
}

TEST(DiagnosticsKs, AsymptoticBranchContinuesTheExactOne) {
  // The last exact n and the first asymptotic n at the same sqrt(n) D: within the asymptotic
  // form's documented error (0.6% for p >= 1e-4 at n = 1000) plus the change of n.
  for (const double lambda : {0.6, 0.9, 1.2, 1.36, 1.63, 2.0}) {
    const double exact = ks_p_value(lambda / std::sqrt(1000.0), 1000);
    const double asymptotic = ks_p_value(lambda / std::sqrt(1001.0), 1001);
    EXPECT_NEAR(asymptotic / exact, 1.0, 0.01) << lambda;
  }
}

TEST(DiagnosticsKs, UniformDrawsAreAccepted) {
  RandomStream rng({.key = 21});
  std::vector<double> values(1000);
  for (double& v : values) v = rng.uniform();
  const KsResult r = ks_uniform(values);
  EXPECT_EQ(r.n, 1000u);
  EXPECT_GT(r.p_value, 1e-3);  // fails for one seed in 1000 under the null
}

TEST(DiagnosticsKs, SkewedDrawsAreRejected) {
  // U^2 has CDF sqrt(x): D ~ max (sqrt(x) - x) = 1/4, so p ~ 2 exp(-2 n / 16) ~ 1e-27 at n = 500.
  RandomStream rng({.key = 22});
  std::vector<double> values(500);
  for (double& v : values) {
    const double u = rng.uniform();
    v = u * u;
  }
  const KsResult r = ks_uniform(values);
  EXPECT_NEAR(r.statistic, 0.25, 0.07);  // 0.07 ~ 1.63 / sqrt(500), the 1% point
  EXPECT_LT(r.p_value, 1e-6);
  EXPECT_GT(r.p_value, 0.0);  // the upper tail is computed, not 1 - 1
}

TEST(DiagnosticsKs, PValuesAreCalibrated) {
  // 1000 fixed-seed samples of n = 50 uniforms: D is continuous, so p is Uniform(0, 1) and the
  // count below a level q is Binomial(1000, q). Bands of 4 standard deviations (each missed with
  // probability ~6e-5): 50 ± 27.6 below 0.05, 500 ± 63.2 below 0.5.
  int below_5_percent = 0;
  int below_half = 0;
  for (std::uint32_t rep = 0; rep < 1000; ++rep) {
    RandomStream rng({.key = 23, .sample = rep});
    std::vector<double> values(50);
    for (double& v : values) v = rng.uniform();
    const double p = ks_uniform(values).p_value;
    below_5_percent += p < 0.05 ? 1 : 0;
    below_half += p < 0.5 ? 1 : 0;
  }
  EXPECT_GE(below_5_percent, 23);
  EXPECT_LE(below_5_percent, 77);
  EXPECT_GE(below_half, 437);
  EXPECT_LE(below_half, 563);
}

TEST(DiagnosticsKs, EdgesAndBadInput) {
  EXPECT_EQ(ks_p_value(1.0, 10), 0.0);
  EXPECT_EQ(ks_p_value(0.01, 10), 1.0);  // below 1 / (2n)
  EXPECT_TRUE(std::isnan(ks_p_value(kNaN, 10)));
  EXPECT_TRUE(std::isnan(ks_p_value(0.5, 0)));
  EXPECT_NO_THROW(ks_uniform({0.0, 1.0}));
  EXPECT_THROW(ks_uniform({}), std::invalid_argument);
  EXPECT_THROW(ks_uniform({0.5, 1.5}), std::invalid_argument);
  EXPECT_THROW(ks_uniform({-0.1, 0.5}), std::invalid_argument);
  EXPECT_THROW(ks_uniform({0.5, kNaN}), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Binomial

// The definition written out: the sum of pmf(i) over every i with pmf(i) <= pmf(x) (1 + 1e-7),
// with the pmf from lgamma.
double binomial_reference(std::uint64_t x, std::uint64_t n, double p) {
  const auto log_pmf = [n, p](std::uint64_t i) {
    const double nd = static_cast<double>(n);
    const double id = static_cast<double>(i);
    return std::lgamma(nd + 1.0) - std::lgamma(id + 1.0) - std::lgamma(nd - id + 1.0) +
           id * std::log(p) + (nd - id) * std::log1p(-p);
  };
  const double limit = log_pmf(x) + std::log1p(1e-7);
  long double sum = 0.0L;
  for (std::uint64_t i = 0; i <= n; ++i) {
    const double l = log_pmf(i);
    if (l <= limit) sum += std::exp(static_cast<long double>(l));
  }
  return std::min(1.0, static_cast<double>(sum));
}

TEST(DiagnosticsBinomial, KnownValues) {
  // P(X <= 3) = (1 + 10 + 45 + 120) / 1024 and the mirror tail: 352 / 1024.
  EXPECT_NEAR(binomial_test_p_value(3, 10, 0.5), 0.34375, 1e-15);
  EXPECT_NEAR(binomial_test_p_value(7, 10, 0.5), 0.34375, 1e-15);
  // 0 of 20 at 0.05: pmf(0) = 0.95^20 = 0.3585 is below pmf(1) = 0.3774 only, so p = 1 - pmf(1).
  EXPECT_NEAR(binomial_test_p_value(0, 20, 0.05), 1.0 - 20.0 * 0.05 * std::pow(0.95, 19), 1e-14);
  EXPECT_NEAR(binomial_test_p_value(0, 20, 0.05), 0.6226464, 1e-7);
  // R's ?binom.test example (Mendel's peas): binom.test(682, 925, p = 0.75) gives p = 0.3825.
  // The definition enumerated in 30-digit arithmetic (mpmath): 0.38249155957485168.
  EXPECT_NEAR(binomial_test_p_value(682, 925, 0.75), 0.3825, 5e-5);
  EXPECT_NEAR(binomial_test_p_value(682, 925, 0.75), 0.38249155957485168, 1e-13);
  // The observed outcome at the mean is as likely as anything: p = 1.
  EXPECT_EQ(binomial_test_p_value(5, 10, 0.5), 1.0);
}

TEST(DiagnosticsBinomial, MatchesTheDefinitionEnumerated) {
  for (const std::uint64_t n : {1, 2, 3, 5, 10, 17, 30, 61, 200}) {
    for (const double p : {0.5, 0.3, 1.0 / 3.0, 0.05, 0.9, 0.999}) {
      for (std::uint64_t x = 0; x <= n; ++x) {
        const double expected = binomial_reference(x, n, p);
        EXPECT_NEAR(binomial_test_p_value(x, n, p), expected, 1e-12 + 1e-9 * expected)
            << x << " of " << n << " at " << p;
      }
    }
  }
}

TEST(DiagnosticsBinomial, LargeCounts) {
  // 10^5 trials: against the enumerated definition.
  for (const std::uint64_t x : {29'500, 29'800, 30'000, 30'300, 31'000}) {
    const double expected = binomial_reference(x, 100'000, 0.3);
    EXPECT_NEAR(binomial_test_p_value(x, 100'000, 0.3) / expected, 1.0, 1e-9) << x;
  }
  // 10^6 fair trials, 1000 above the mean (2 sd): with the continuity correction the normal
  // approximation is 2 (1 - Phi(999.5 / 500)), good to well under 1% here.
  const double normal = std::erfc(999.5 / 500.0 / std::sqrt(2.0));
  EXPECT_NEAR(binomial_test_p_value(501'000, 1'000'000, 0.5) / normal, 1.0, 0.01);
  // 10^12 trials: the bisection visits ~40 outcomes, not 10^12.
  EXPECT_NEAR(binomial_test_p_value(500'001'000'000, 1'000'000'000'000, 0.5),
              std::erfc(999'999.5 / 500'000.0 / std::sqrt(2.0)), 1e-3);
}

TEST(DiagnosticsBinomial, DegenerateAndBadInput) {
  EXPECT_EQ(binomial_test_p_value(0, 0, 0.3), 1.0);
  EXPECT_EQ(binomial_test_p_value(0, 10, 0.0), 1.0);
  EXPECT_EQ(binomial_test_p_value(1, 10, 0.0), 0.0);
  EXPECT_EQ(binomial_test_p_value(10, 10, 1.0), 1.0);
  EXPECT_EQ(binomial_test_p_value(9, 10, 1.0), 0.0);
  EXPECT_THROW(binomial_test_p_value(11, 10, 0.5), std::invalid_argument);
  EXPECT_THROW(binomial_test_p_value(1, 10, -0.1), std::invalid_argument);
  EXPECT_THROW(binomial_test_p_value(1, 10, 1.1), std::invalid_argument);
  EXPECT_THROW(binomial_test_p_value(1, 10, kNaN), std::invalid_argument);
  EXPECT_THROW(binomial_test_p_value(1, (std::uint64_t{1} << 53) + 1, 0.5), std::invalid_argument);
}

// P(X >= x): against the sum of the pmf, and the edge cases.
TEST(DiagnosticsBinomial, UpperTail) {
  // 0.95^20 = P(X = 0) at n = 20, p = 0.05, so P(X >= 1) = 1 - 0.95^20.
  EXPECT_NEAR(binomial_upper_p_value(1, 20, 0.05), 1.0 - std::pow(0.95, 20), 1e-14);
  // 8 of 10 at 1/2: (45 + 10 + 1) / 1024.
  EXPECT_NEAR(binomial_upper_p_value(8, 10, 0.5), 56.0 / 1024.0, 1e-15);
  EXPECT_NEAR(binomial_upper_p_value(10, 10, 0.5), 1.0 / 1024.0, 1e-17);
  for (const std::uint64_t n : {1, 7, 100}) {
    for (const double p : {0.05, 0.5, 0.9}) {
      for (std::uint64_t x = 0; x <= n; ++x) {
        long double sum = 0.0L;
        for (std::uint64_t i = x; i <= n; ++i) {
          sum += std::exp(static_cast<long double>(
              std::lgamma(n + 1.0) - std::lgamma(i + 1.0) - std::lgamma(n - i + 1.0) +
              static_cast<double>(i) * std::log(p) + static_cast<double>(n - i) * std::log1p(-p)));
        }
        const double expected = std::min(1.0, static_cast<double>(sum));
        EXPECT_NEAR(binomial_upper_p_value(x, n, p), expected, 1e-12 + 1e-9 * expected)
            << x << " of " << n << " at " << p;
      }
    }
  }
  EXPECT_EQ(binomial_upper_p_value(0, 10, 0.3), 1.0);
  EXPECT_EQ(binomial_upper_p_value(0, 0, 0.3), 1.0);
  EXPECT_EQ(binomial_upper_p_value(1, 10, 0.0), 0.0);
  EXPECT_EQ(binomial_upper_p_value(10, 10, 1.0), 1.0);
  EXPECT_THROW(binomial_upper_p_value(11, 10, 0.5), std::invalid_argument);
  EXPECT_THROW(binomial_upper_p_value(1, 10, kNaN), std::invalid_argument);
}

}  // namespace
}  // namespace pcbench
