#include "harness/verify/statistics.h"

#include <gtest/gtest.h>

#include <boost/math/distributions/binomial.hpp>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "base/rng.h"
#include "harness/plan/plan.h"
#include "harness/run/runner.h"
#include "harness/verify/rounding_bound.h"

namespace pcbench {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::vector<ReplicateResult> replicates_of(const std::vector<double>& estimates,
                                           double cpu_seconds = 0.5) {
  std::vector<ReplicateResult> out;
  for (double e : estimates) {
    ReplicateResult r;
    r.estimate = e;
    r.cpu_seconds = cpu_seconds;
    r.seconds = cpu_seconds;
    out.push_back(r);
  }
  return out;
}

Reference exact(double value) {
  return {.value = value, .kind = ReferenceKind::kExact};
}

// Hand-made replicate estimates have no per-sample arithmetic for the rounding bound to count.
constexpr double kHandMade = 0.0;

// ---------------------------------------------------------------------------------------------
// Student's t

TEST(StatisticsStudentT, KnownTwoSidedPValues) {
  EXPECT_NEAR(student_t_p_value(2.0, 10), 0.0733880, 5e-7);
  EXPECT_NEAR(student_t_p_value(-2.0, 10), 0.0733880, 5e-7);
  EXPECT_EQ(student_t_p_value(0.0, 10), 1.0);
  // Tabulated two-sided 5% critical values.
  EXPECT_NEAR(student_t_p_value(12.706204736, 1), 0.05, 1e-9);
  EXPECT_NEAR(student_t_p_value(2.228138852, 10), 0.05, 1e-9);
  EXPECT_NEAR(student_t_p_value(3.169272673, 10), 0.01, 1e-9);
  // Close to the normal for many degrees of freedom.
  EXPECT_NEAR(student_t_p_value(1.959963985, 1e7), 0.05, 1e-6);
}

TEST(StatisticsStudentT, InfiniteAndNanStatistics) {
  EXPECT_EQ(student_t_p_value(kInf, 5), 0.0);
  EXPECT_EQ(student_t_p_value(-kInf, 5), 0.0);
  EXPECT_TRUE(std::isnan(student_t_p_value(std::nan(""), 5)));
}

// ---------------------------------------------------------------------------------------------
// aggregate

TEST(StatisticsAggregate, FiguresOfAHandMadeRun) {
  // Estimates 1, 2, 3, 4 against the exact value 2; N = 100 samples and 0.5 CPU s per replicate.
  const Aggregates a = aggregate(replicates_of({1, 2, 3, 4}), exact(2.0), 100);
  const double replicate_variance = 5.0 / 3.0;  // sum of squared deviations 5, R - 1 = 3
  EXPECT_DOUBLE_EQ(a.mean, 2.5);
  EXPECT_DOUBLE_EQ(a.stderr_of_mean, std::sqrt(replicate_variance / 4.0));
  EXPECT_DOUBLE_EQ(a.bias, 0.5);
  EXPECT_DOUBLE_EQ(a.rmse, std::sqrt((1.0 + 0.0 + 1.0 + 4.0) / 4.0));
  EXPECT_DOUBLE_EQ(a.rel_mse, 1.5 / 4.0);
  EXPECT_DOUBLE_EQ(a.seconds_per_sample, 2.0 / 400.0);
  // 1 / (N Var_rep × cpu_seconds / (R N)).
  EXPECT_DOUBLE_EQ(a.efficiency, 1.0 / (100.0 * replicate_variance * (2.0 / (4.0 * 100.0))));
  EXPECT_NEAR(a.efficiency, 1.2, 1e-12);
}

TEST(StatisticsAggregate, UnequalCpuTimesAreSummed) {
  std::vector<ReplicateResult> reps = replicates_of({0.0, 2.0});
  reps[0].cpu_seconds = 1.0;
  reps[1].cpu_seconds = 3.0;
  const Aggregates a = aggregate(reps, exact(1.0), 10);
  EXPECT_DOUBLE_EQ(a.seconds_per_sample, 4.0 / 20.0);
  // Var_rep = 2; per-sample variance 20; efficiency 1 / (20 × 0.2).
  EXPECT_DOUBLE_EQ(a.efficiency, 0.25);
  EXPECT_DOUBLE_EQ(a.bias, 0.0);
  EXPECT_DOUBLE_EQ(a.rmse, 1.0);
}

TEST(StatisticsAggregate, WithoutAReferenceBiasAndErrorsAreUndefined) {
  const Aggregates a = aggregate(replicates_of({1, 2, 3, 4}), Reference{}, 100);
  EXPECT_DOUBLE_EQ(a.mean, 2.5);
  EXPECT_DOUBLE_EQ(a.stderr_of_mean, std::sqrt(5.0 / 12.0));
  EXPECT_TRUE(std::isnan(a.bias));
  EXPECT_TRUE(std::isnan(a.rmse));
  EXPECT_TRUE(std::isnan(a.rel_mse));
  EXPECT_TRUE(std::isfinite(a.efficiency));
}

TEST(StatisticsAggregate, ZeroReferenceLeavesRelativeMseUndefined) {
  const Aggregates a = aggregate(replicates_of({-1, 1}), exact(0.0), 10);
  EXPECT_DOUBLE_EQ(a.bias, 0.0);
  EXPECT_DOUBLE_EQ(a.rmse, 1.0);
  EXPECT_TRUE(std::isnan(a.rel_mse));
}

// ---------------------------------------------------------------------------------------------
// test_against_reference

TEST(StatisticsTest, NoReferenceIsInconclusiveAndNotTested) {
  const Verdict v =
      test_against_reference(replicates_of({1, 2, 3}), Reference{}, "consistent", kHandMade);
  EXPECT_FALSE(v.tested);
  EXPECT_EQ(v.test, "none");
  EXPECT_EQ(v.result, "inconclusive");
  EXPECT_FALSE(v.reason.empty());
  EXPECT_EQ(v.expect, "consistent");
  EXPECT_TRUE(std::isnan(v.p_value));
}

TEST(StatisticsTest, OneSampleTOnAHandMadeRun) {
  const Verdict v =
      test_against_reference(replicates_of({1, 2, 3, 4}), exact(2.0), "consistent", kHandMade);
  EXPECT_TRUE(v.tested);
  EXPECT_EQ(v.test, "student_t");
  EXPECT_EQ(v.dof, 3.0);
  EXPECT_DOUBLE_EQ(v.test_stderr, std::sqrt(5.0 / 12.0));
  EXPECT_DOUBLE_EQ(v.statistic, 0.5 / std::sqrt(5.0 / 12.0));  // 0.7746
  // Two-sided p of t = 0.774597 with 3 dof.
  EXPECT_NEAR(v.p_value, 0.4950, 5e-4);
  EXPECT_DOUBLE_EQ(v.p_value, student_t_p_value(v.statistic, 3.0));
  EXPECT_EQ(v.reference_value, 2.0);
}

TEST(StatisticsTest, ZeroSpreadWithoutBiasHasPOne) {
  const Verdict v =
      test_against_reference(replicates_of({2, 2, 2}), exact(2.0), "consistent", kHandMade);
  EXPECT_TRUE(v.tested);
  EXPECT_EQ(v.statistic, 0.0);
  EXPECT_EQ(v.p_value, 1.0);
}

TEST(StatisticsTest, ZeroSpreadWithBiasIsTestedAgainstTheRoundingBound) {
  // No spread: the standard error is the rounding bound u (6 |m| + |r|), and a bias of 1 is
  // 10^14 of them (before the bound, t was infinite and p exactly 0).
  const Verdict above = test_against_reference(replicates_of({2, 2, 2}), exact(1.0), "", kHandMade);
  EXPECT_EQ(above.rounding_bound, kUnitRoundoff * (6.0 * 2.0 + 1.0));
  EXPECT_EQ(above.test_stderr, above.rounding_bound);
  EXPECT_EQ(above.measured_stderr, 0.0);
  EXPECT_DOUBLE_EQ(above.statistic, 1.0 / above.rounding_bound);
  EXPECT_LT(above.p_value, 1e-25);
  const Verdict below = test_against_reference(replicates_of({2, 2, 2}), exact(3.0), "", kHandMade);
  EXPECT_DOUBLE_EQ(below.statistic, -1.0 / below.rounding_bound);
  EXPECT_LT(below.p_value, 1e-25);
}

TEST(StatisticsTest, ZeroSpreadAndZeroBoundIsExact) {
  // All zero: no bound to speak of, and the test stays exact.
  const Verdict v = test_against_reference(replicates_of({0, 0, 0}), exact(0.0), "", kHandMade);
  EXPECT_EQ(v.rounding_bound, 0.0);
  EXPECT_EQ(v.statistic, 0.0);
  EXPECT_EQ(v.p_value, 1.0);
}

TEST(StatisticsTest, WelchWhenTheReferenceHasAnUncertainty) {
  const Reference reference{
      .value = 2.0, .kind = ReferenceKind::kNumerical, .uncertainty = 0.3, .dof = 20};
  const Verdict v =
      test_against_reference(replicates_of({1, 2, 3, 4}), reference, "consistent", kHandMade);
  const double se2 = 5.0 / 12.0, u2 = 0.09;
  EXPECT_EQ(v.test, "welch");
  EXPECT_DOUBLE_EQ(v.test_stderr, std::sqrt(se2 + u2));
  EXPECT_DOUBLE_EQ(v.statistic, 0.5 / std::sqrt(se2 + u2));
  // Welch–Satterthwaite: (se² + u²)² / (se⁴ / (R - 1) + u⁴ / dof_ref).
  EXPECT_DOUBLE_EQ(v.dof, (se2 + u2) * (se2 + u2) / (se2 * se2 / 3.0 + u2 * u2 / 20.0));
  EXPECT_DOUBLE_EQ(v.p_value, student_t_p_value(v.statistic, v.dof));
  EXPECT_GT(v.dof, 3.0);  // the reference's own dof add to the replicates'
}

TEST(StatisticsTest, WelchWithAnInfiniteDofReference) {
  const Reference reference{.value = 2.0, .kind = ReferenceKind::kRendered, .uncertainty = 0.3};
  const Verdict v = test_against_reference(replicates_of({1, 2, 3, 4}), reference, "", kHandMade);
  const double se2 = 5.0 / 12.0, u2 = 0.09;
  EXPECT_EQ(v.test, "welch");
  EXPECT_DOUBLE_EQ(v.dof, (se2 + u2) * (se2 + u2) / (se2 * se2 / 3.0));
  EXPECT_TRUE(std::isfinite(v.p_value));
}

TEST(StatisticsTest, WelchWithZeroSpreadTestsAgainstTheReferenceUncertaintyAlone) {
  const Reference reference{.value = 2.6, .kind = ReferenceKind::kRendered, .uncertainty = 0.3};
  Verdict v = test_against_reference(replicates_of({2, 2, 2}), reference, "", kHandMade);
  EXPECT_EQ(v.test, "welch");
  EXPECT_DOUBLE_EQ(v.statistic, -2.0);
  EXPECT_EQ(v.dof, kInf);
  EXPECT_NEAR(v.p_value, 0.0455003, 1e-6);  // two-sided normal tail beyond 2
  std::vector<Verdict*> family = {&v};
  decide_family(family, 0.05);
  EXPECT_EQ(v.result, "biased");
  EXPECT_NEAR(v.min_detectable_bias, 2.80158 * 0.3, 1e-4);
}

// The paired t on (1, 0.5), (2, 2), (3, 2), (4, 3): differences 0.5, 0, 1, 1, mean 0.625,
// variance 0.6875 / 3; t = 2.6111648, p = 0.0796050 (scipy.stats.ttest_rel gives both).
TEST(StatisticsPairedT, HandMadePairs) {
  const std::vector<double> a = {1, 2, 3, 4}, b = {0.5, 2, 2, 3};
  const TwoSampleTest t = paired_t_test(a, b);
  EXPECT_DOUBLE_EQ(t.mean_a, 2.5);
  EXPECT_DOUBLE_EQ(t.mean_b, 1.875);
  EXPECT_DOUBLE_EQ(t.stderr_of_difference, std::sqrt(0.6875 / 3.0 / 4.0));
  EXPECT_NEAR(t.statistic, 2.6111648393354674, 1e-12);
  EXPECT_EQ(t.dof, 3.0);
  EXPECT_NEAR(t.p_value, 0.07960498081790625, 1e-9);
  // Welch on the same numbers ignores the pairing: a larger standard error here.
  EXPECT_GT(welch_two_sample(a, b).stderr_of_difference, 2.0 * t.stderr_of_difference);
}

TEST(StatisticsPairedT, ConstantDifferencesAreExact) {
  const std::vector<double> a = {1, 2, 3}, shifted = {1.5, 2.5, 3.5};
  const TwoSampleTest same = paired_t_test(a, a);
  EXPECT_EQ(same.p_value, 1.0);
  EXPECT_EQ(same.statistic, 0.0);
  EXPECT_EQ(same.dof, 2.0);
  const TwoSampleTest apart = paired_t_test(a, shifted);
  EXPECT_EQ(apart.p_value, 0.0);
  EXPECT_EQ(apart.statistic, -kInf);
}

TEST(StatisticsPairedT, UnequalLengthsAreNoPairs) {
  const std::vector<double> a = {1, 2, 3}, b = {1, 2};
  EXPECT_THROW(paired_t_test(a, b), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// The rounding bound (harness/verify/rounding_bound.h)

// R replicates that all gave `estimate`, each from samples of Σ|terms| = `mean_abs`: a constant
// integrand.
std::vector<ReplicateResult> constant_replicates(double estimate, double mean_abs,
                                                 std::size_t count = 8) {
  std::vector<ReplicateResult> out = replicates_of(std::vector<double>(count, estimate));
  for (ReplicateResult& r : out) r.mean_abs = mean_abs;
  return out;
}

// The verdict of `v` alone in a family at alpha = 0.01.
Verdict decided(Verdict v) {
  std::vector<Verdict*> family = {&v};
  decide_family(family, 0.01);
  return v;
}

TEST(StatisticsRoundingBound, SampleRoundingsCountTermsAndImportanceEvaluations) {
  // vc-all at M = 16: 16 connections per camera sample, no importance.
  EXPECT_EQ(sample_roundings({.camera_paths = 100, .connections = 1600}), kTermRoundings + 16.0);
  // pcbpt at M = 64, K = 4: P's normaliser sums 64 importances.
  EXPECT_EQ(
      sample_roundings({.camera_paths = 10, .connections = 40, .importance_evaluations = 640}),
      kTermRoundings + 68.0);
  EXPECT_EQ(sample_roundings({}), kTermRoundings);
}

TEST(StatisticsRoundingBound, IsUnitRoundoffTimesTheStatedCounts) {
  std::vector<ReplicateResult> reps = constant_replicates(-0.5, 2.0, 4);
  EXPECT_EQ(rounding_bound(reps, 31.0), kUnitRoundoff * (31.0 * 2.0 + 6.0 * 0.5));
  // Against a reference its half ulp joins: u (s A + 6 |m| + |r|).
  const Verdict v = test_against_reference(reps, exact(-0.25), "", 31.0);
  EXPECT_EQ(v.rounding_bound, kUnitRoundoff * (31.0 * 2.0 + 6.0 * 0.5 + 0.25));
}

TEST(StatisticsRoundingBound, AConstantIntegrandOneUlpOffIsConsistent) {
  // vc-all at M = 16 on f = 0.1 gave 0.1 + 1 ulp in every replicate (a plain sum of 16 terms):
  // before the bound, "differs by inf standard errors".
  const double one_ulp_above = std::nextafter(0.1, 1.0);
  const Verdict v =
      decided(test_against_reference(constant_replicates(one_ulp_above, one_ulp_above), exact(0.1),
                                     "consistent", kTermRoundings + 16.0));
  EXPECT_EQ(v.measured_stderr, 0.0);
  EXPECT_GT(v.rounding_bound, one_ulp_above - 0.1);
  EXPECT_EQ(v.test_stderr, v.rounding_bound);
  EXPECT_EQ(v.result, "consistent") << v.reason;
  EXPECT_NE(v.reason.find("standard error 0 below the rounding bound"), std::string::npos)
      << v.reason;
  EXPECT_NE(v.reason.find("tested against the rounding bound; no evidence of bias"),
            std::string::npos)
      << v.reason;
  // What the test could detect is a few bounds, not 0.
  EXPECT_GT(v.min_detectable_bias, v.rounding_bound);
  EXPECT_LT(v.min_detectable_bias, 10.0 * v.rounding_bound);
}

TEST(StatisticsRoundingBound, AConstantIntegrandAgainstAWrongExactValueIsBiased) {
  const Verdict v = decided(test_against_reference(constant_replicates(0.1, 0.1), exact(0.1000001),
                                                   "biased", kTermRoundings + 16.0));
  EXPECT_EQ(v.result, "biased") << v.reason;
  EXPECT_LT(v.p_value, 1e-50);  // t = 2.4e8 with 7 dof
  EXPECT_NE(v.reason.find("tested against the rounding bound; the mean differs from the "
                          "reference by"),
            std::string::npos)
      << v.reason;
  EXPECT_NE(v.reason.find("rounding bounds"), std::string::npos) << v.reason;
}

TEST(StatisticsRoundingBound, ASpreadAboveTheBoundIsTestedAsBefore) {
  const Verdict v = decided(test_against_reference(replicates_of({1, 2, 3, 4}), exact(2.0),
                                                   "consistent", kTermRoundings));
  EXPECT_GT(v.rounding_bound, 0.0);
  EXPECT_EQ(v.test_stderr, v.measured_stderr);
  EXPECT_DOUBLE_EQ(v.test_stderr, std::sqrt(5.0 / 12.0));
  EXPECT_EQ(v.reason.find("rounding bound"), std::string::npos) << v.reason;
}

TEST(StatisticsRoundingBound, TwoSampleTestOfTwoConstantsOneUlpApart) {
  const double one_ulp_above = std::nextafter(0.1, 1.0);
  const std::vector<double> a(8, 0.1), b(8, one_ulp_above);
  const TwoSampleTest raw = welch_two_sample(a, b);
  EXPECT_EQ(raw.p_value, 0.0);  // what the pairwise comparison said before the bound
  const double bound =
      rounding_bound(constant_replicates(0.1, 0.1), kTermRoundings + 16.0) +
      rounding_bound(constant_replicates(one_ulp_above, one_ulp_above), kTermRoundings + 16.0);
  const TwoSampleTest floored = with_rounding_floor(raw, bound);
  EXPECT_EQ(floored.stderr_of_difference, bound);
  EXPECT_EQ(floored.dof, raw.dof);
  const Verdict v = decided(two_sample_verdict(floored, "consistent"));
  EXPECT_EQ(v.result, "consistent") << v.reason;
  EXPECT_NE(v.reason.find("below the rounding bound"), std::string::npos) << v.reason;

  const std::vector<double> c(8, 0.1000001);
  EXPECT_EQ(
      decided(two_sample_verdict(with_rounding_floor(welch_two_sample(a, c), bound), "")).result,
      "biased");
  // Samples that vary are tested as before.
  const TwoSampleTest spread =
      welch_two_sample(std::vector<double>{1, 2, 3}, std::vector<double>{2, 3, 4});
  const TwoSampleTest kept = with_rounding_floor(spread, bound);
  EXPECT_EQ(kept.stderr_of_difference, spread.stderr_of_difference);
  EXPECT_EQ(kept.p_value, spread.p_value);
}

// ---------------------------------------------------------------------------------------------
// decide_family

Verdict tested_with_p(double p, double test_stderr = 1.0, double dof = 30.0) {
  Verdict v;
  v.tested = true;
  v.p_value = p;
  v.test_stderr = test_stderr;
  v.dof = dof;
  v.reference_value = 2.0;
  return v;
}

TEST(StatisticsHolm, AdjustsAKnownExample) {
  Verdict a = tested_with_p(0.01), b = tested_with_p(0.04), c = tested_with_p(0.03);
  std::vector<Verdict*> family = {&a, &b, &c};
  decide_family(family, 0.05);
  // Sorted: 0.01 × 3 = 0.03; 0.03 × 2 = 0.06; 0.04 × 1 = 0.04, raised to the running max 0.06.
  EXPECT_NEAR(a.p_adjusted, 0.03, 1e-15);
  EXPECT_NEAR(b.p_adjusted, 0.06, 1e-15);
  EXPECT_NEAR(c.p_adjusted, 0.06, 1e-15);
  EXPECT_EQ(a.result, "biased");
  EXPECT_EQ(b.result, "consistent");
  EXPECT_EQ(c.result, "consistent");
  for (const Verdict* v : family) EXPECT_EQ(v->alpha, 0.05);
  // The raw p-values are kept.
  EXPECT_EQ(a.p_value, 0.01);
  EXPECT_EQ(b.p_value, 0.04);
}

TEST(StatisticsHolm, AdjustedPValuesAreCappedAtOne) {
  Verdict a = tested_with_p(0.6), b = tested_with_p(0.9);
  std::vector<Verdict*> family = {&a, &b};
  decide_family(family, 0.05);
  EXPECT_EQ(a.p_adjusted, 1.0);
  EXPECT_EQ(b.p_adjusted, 1.0);
}

TEST(StatisticsHolm, BiasedExactlyWhenAdjustedPIsAtMostAlpha) {
  // Exactly representable: 0.25 × 2 = 0.5 and 0.5 × 1 = 0.5.
  Verdict a = tested_with_p(0.25), b = tested_with_p(0.5);
  std::vector<Verdict*> family = {&a, &b};
  decide_family(family, 0.5);
  EXPECT_EQ(a.p_adjusted, 0.5);
  EXPECT_EQ(a.result, "biased");  // p_adjusted == alpha rejects
  EXPECT_EQ(b.result, "biased");
  decide_family(family, std::nextafter(0.5, 0.0));
  EXPECT_EQ(a.result, "consistent");
  EXPECT_EQ(b.result, "consistent");

  std::vector<Verdict> many;
  for (double p : {1e-6, 0.001, 0.004, 0.01, 0.02, 0.2, 0.5, 0.9}) many.push_back(tested_with_p(p));
  std::vector<Verdict*> pointers;
  for (Verdict& v : many) pointers.push_back(&v);
  decide_family(pointers, 0.05);
  for (const Verdict& v : many) {
    EXPECT_GE(v.p_adjusted, v.p_value);
    EXPECT_EQ(v.result, v.p_adjusted <= 0.05 ? "biased" : "consistent") << v.p_value;
    EXPECT_FALSE(v.reason.empty());
  }
}

TEST(StatisticsHolm, UntestedAndNullVerdictsDoNotCountInTheFamily) {
  Verdict a = tested_with_p(0.01), b = tested_with_p(0.04), c = tested_with_p(0.03);
  Verdict untested =
      test_against_reference(replicates_of({1, 2}), Reference{}, "consistent", kHandMade);
  std::vector<Verdict*> family = {&a, nullptr, &untested, &b, &c};
  decide_family(family, 0.05);
  EXPECT_NEAR(a.p_adjusted, 0.03, 1e-15);  // m = 3, not 4 or 5
  EXPECT_NEAR(b.p_adjusted, 0.06, 1e-15);
  EXPECT_EQ(untested.result, "inconclusive");
  EXPECT_EQ(untested.alpha, 0.05);
}

TEST(StatisticsHolm, MinimumDetectableBiasScalesWithTheStandardError) {
  Verdict small = tested_with_p(0.5, 1.0, 1e6), large = tested_with_p(0.5, 2.0, 1e6);
  std::vector<Verdict*> one = {&small};
  decide_family(one, 0.05);
  // With m = 1 and many dof: (z_{0.975} + z_{0.8}) × stderr = (1.95996 + 0.84162) × stderr.
  EXPECT_NEAR(small.min_detectable_bias, 2.80158, 1e-4);
  EXPECT_NEAR(small.min_detectable_rel_bias, 2.80158 / 2.0, 1e-4);

  std::vector<Verdict*> two = {&small, &large};
  decide_family(two, 0.05);
  EXPECT_GT(small.min_detectable_bias, 0.0);
  EXPECT_DOUBLE_EQ(large.min_detectable_bias, 2.0 * small.min_detectable_bias);
  // The Bonferroni share alpha / 2 makes the detectable bias larger than with m = 1.
  EXPECT_GT(small.min_detectable_bias, 2.80158 + 1e-3);
}

// A bias of k × the sample's own detectable bias moves its statistic by k × the multiplier: at
// k = 1 the test rejects with the promised power, whatever the dof; at k = 0 with the level.
TEST(StatisticsPower, ShiftedTPowerAtTheDetectableBiasIsThePower) {
  for (const double dof : {3.0, 7.0, 14.5, 1e6}) {
    for (const double share : {0.05, 0.05 / 12.0, 1e-4}) {
      const double m = detectable_multiplier(share, dof, 0.8);
      // The far tail P(T < -c - m), below P(T < -c) = share / 2, is all that is added to 0.8.
      EXPECT_GE(shifted_t_power(m, dof, share), 0.8 - 1e-12) << dof << " " << share;
      EXPECT_LE(shifted_t_power(m, dof, share), 0.8 + share / 2.0) << dof << " " << share;
      EXPECT_NEAR(shifted_t_power(0.0, dof, share), share, 1e-9 * share);
      EXPECT_LT(shifted_t_power(0.5 * m, dof, share), 0.8);
      EXPECT_GT(shifted_t_power(2.0 * m, dof, share), 0.8);
    }
  }
  // Large dof: the normal Φ(m - z) + Φ(-m - z) with m = z_{0.975} + z_{0.8}: 0.8 + Φ(-4.76).
  EXPECT_NEAR(shifted_t_power(1.95996398 + 0.84162123, 1e9, 0.05), 0.8 + 9.6e-7, 1e-7);
}

// The noncentral t power: α at no bias; at large dof the normal formula Φ(δ - z) + Φ(-δ - z).
TEST(StatisticsPower, NoncentralTPower) {
  EXPECT_EQ(noncentral_t_power(0.0, 7.0, 0.05), 0.05);
  EXPECT_NEAR(noncentral_t_power(1.95996398 + 0.84162123, 1e7, 0.05), 0.8 + 9.6e-7, 1e-6);
  // Fewer dof: a heavier null tail pushes the critical value out, so less power.
  EXPECT_LT(noncentral_t_power(3.0, 7.0, 0.05), noncentral_t_power(3.0, 70.0, 0.05));
  EXPECT_NEAR(noncentral_t_power(-3.0, 7.0, 0.05), noncentral_t_power(3.0, 7.0, 0.05), 1e-15);
}

TEST(StatisticsHolm, MinimumDetectableRelativeBiasIsUndefinedForAZeroReference) {
  Verdict v = tested_with_p(0.5);
  v.reference_value = 0.0;
  std::vector<Verdict*> family = {&v};
  decide_family(family, 0.01);
  EXPECT_GT(v.min_detectable_bias, 0.0);
  EXPECT_TRUE(std::isnan(v.min_detectable_rel_bias));
}

// ---------------------------------------------------------------------------------------------
// Calibration of the one-sample t test.
//
// 2000 simulated runs of 8 replicates each, the replicate estimates normal with the reference as
// mean. At alpha = 0.05 the number of false alarms is Binomial(2000, 0.05) for a correctly sized
// test. The acceptance band holds that count with probability >= 1 - 1e-4 (false-alarm budget
// 1e-4, split evenly between the tails). A test that used the normal instead of Student's t with
// 7 dof rejects about 9.1% of runs (182 expected) and falls far outside the band. Fixed keys: the
// outcome is deterministic.

double standard_normal(RandomStream& rng) {
  // Box–Muller; 1 - u is in (0, 1], so the logarithm is finite.
  const double u1 = 1.0 - rng.uniform();
  const double u2 = rng.uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

TEST(StatisticsCalibration, OneSampleTFalseAlarmRateIsAlpha) {
  constexpr int kRuns = 2000;
  constexpr int kReplicates = 8;
  constexpr double kAlpha = 0.05;
  constexpr double kBudget = 1e-4;
  const double reference = 3.5, sigma = 0.2;

  int false_alarms = 0;
  for (int run = 0; run < kRuns; ++run) {
    RandomStream rng({.key = 0x5eed2024,
                      .replicate = static_cast<std::uint32_t>(run),
                      .purpose = StreamPurpose::kEstimatorAux});
    std::vector<double> estimates(kReplicates);
    for (double& e : estimates) e = reference + sigma * standard_normal(rng);
    const Verdict v =
        test_against_reference(replicates_of(estimates), exact(reference), "consistent", kHandMade);
    ASSERT_EQ(v.test, "student_t");
    if (v.p_value <= kAlpha) ++false_alarms;
  }
  RecordProperty("false_alarms", false_alarms);
  const boost::math::binomial distribution(kRuns, kAlpha);
  const double low = boost::math::quantile(distribution, kBudget / 2.0);
  const double high = boost::math::quantile(boost::math::complement(distribution, kBudget / 2.0));
  EXPECT_GE(false_alarms, low) << "band [" << low << ", " << high << "]";
  EXPECT_LE(false_alarms, high) << "band [" << low << ", " << high << "]";
  // The band is informative: it excludes the normal-approximation rate of about 9.1%.
  EXPECT_LT(high, 0.08 * kRuns);
}

}  // namespace
}  // namespace pcbench

namespace pcbench {
namespace {

// The guards that make a run inconclusive: a heavy tail counts only with a dominant largest
// sample (a high k̂ on bounded, clustered samples does not), and too few effective samples.
TEST(StatisticsGuards, StatedReasonsOnly) {
  const SampleDiagnostics heavy{
      .tail_shape = 0.75, .tail_size = 900, .largest_share = 0.4, .min_effective_samples = 500};
  const SampleDiagnostics clustered{
      .tail_shape = 2.1, .tail_size = 900, .largest_share = 0.001, .min_effective_samples = 5000};
  const SampleDiagnostics finite{
      .tail_shape = 0.3, .tail_size = 900, .largest_share = 0.005, .min_effective_samples = 5000};
  const SampleDiagnostics sparse{
      .tail_shape = -0.5, .tail_size = 3, .largest_share = 0.3, .min_effective_samples = 3};
  ASSERT_TRUE(untestable_reason(heavy).has_value());
  EXPECT_NE(untestable_reason(heavy)->find("variance may be infinite"), std::string::npos);
  EXPECT_FALSE(untestable_reason(clustered).has_value());
  EXPECT_FALSE(untestable_reason(finite).has_value());
  ASSERT_TRUE(untestable_reason(sparse).has_value());
  EXPECT_NE(untestable_reason(sparse)->find("too few effective samples"), std::string::npos);
}

// A width-1e-6 peak hit by few samples is inconclusive, never a confident wrong verdict.
TEST(StatisticsGuards, NarrowPeakIsInconclusiveNotWrong) {
  const RunPlan plan = plan_runs({GridRequest{.estimators = {"plain"},
                                              .integrands = {"narrow-peak"},
                                              .params = {{"width", {"1e-6"}}},
                                              .samples = 20000,
                                              .replicates = 16,
                                              .where = "test"}},
                                 {})[0];
  const RunResult result = execute_run(plan, {.seed = 3});
  const SampleDiagnostics d = diagnose_samples(result.replicates);
  ASSERT_TRUE(untestable_reason(d).has_value()) << d.min_effective_samples;
}

}  // namespace
}  // namespace pcbench
