#include "base/tally.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "base/rng.h"

namespace pcbench {
namespace {

std::vector<double> random_values(std::size_t n, double offset) {
  RandomStream rng({.key = 77});
  std::vector<double> values(n);
  for (double& v : values) v = offset + rng.uniform();
  return values;
}

TEST(TallyWelford, MatchesTwoPassMeanAndVariance) {
  const std::vector<double> values = random_values(10000, 0.0);
  Tally tally;
  for (std::size_t i = 0; i < values.size(); ++i) tally.add(values[i], i);
  long double sum = 0;
  for (double v : values) sum += v;
  const long double mean = sum / values.size();
  long double m2 = 0;
  for (double v : values) m2 += (v - mean) * (v - mean);
  EXPECT_NEAR(tally.mean(), static_cast<double>(mean), 1e-15);
  EXPECT_NEAR(tally.variance(), static_cast<double>(m2 / (values.size() - 1)), 1e-15);
  EXPECT_EQ(tally.count(), values.size());
}

// A large offset defeats the textbook one-pass formula sum(x²)/n - mean²; Welford keeps digits.
TEST(TallyWelford, KeepsVarianceUnderALargeOffset) {
  const std::vector<double> values = random_values(10000, 1e9);
  Tally tally;
  for (std::size_t i = 0; i < values.size(); ++i) tally.add(values[i], i);
  EXPECT_NEAR(tally.variance(), 1.0 / 12.0, 0.005);  // uniform variance; 10^4 samples
}

TEST(TallyChanMerge, EqualsOneTallyOverAllSamples) {
  const std::vector<double> values = random_values(9999, 3.0);
  Tally whole, first, second, third;
  for (std::size_t i = 0; i < values.size(); ++i) {
    whole.add(values[i], i);
    (i < 1000 ? first : i < 7000 ? second : third).add(values[i], i);
  }
  first.merge(second);
  first.merge(third);
  EXPECT_EQ(first.count(), whole.count());
  EXPECT_NEAR(first.mean(), whole.mean(), 1e-14);
  EXPECT_NEAR(first.variance(), whole.variance(), 1e-13);
}

TEST(TallyChanMerge, IntoAnEmptyTallyCopies) {
  Tally empty, other;
  other.add(1.0, 0);
  other.add(3.0, 1);
  empty.merge(other);
  EXPECT_EQ(empty.mean(), 2.0);
  EXPECT_EQ(empty.variance(), 2.0);
}

// 1 + 1e-16 × 10^6 - 1: plain summation loses the small terms entirely.
TEST(TallyCompensatedSum, KeepsSmallTermsBesideALargeOne) {
  CompensatedSum sum;
  sum.add(1.0);
  for (int i = 0; i < 1000000; ++i) sum.add(1e-16);
  sum.add(-1.0);
  EXPECT_NEAR(sum.value(), 1e-10, 1e-20);
}

TEST(TallyNonfinite, CountedNeverDroppedAndFirstLocated) {
  Tally a, b;
  a.add(1.0, 0);
  a.add(2.0, 1);
  b.add(std::numeric_limits<double>::infinity(), 5);
  b.add(std::numeric_limits<double>::quiet_NaN(), 6);
  b.add(4.0, 7);
  a.merge(b);
  EXPECT_EQ(a.nonfinite_count(), 2u);
  EXPECT_EQ(a.finite_count(), 3u);
  EXPECT_EQ(a.count(), 5u);
  ASSERT_TRUE(a.first_nonfinite_sample().has_value());
  EXPECT_EQ(*a.first_nonfinite_sample(), 5u);
  EXPECT_TRUE(std::isnan(a.mean()));      // the NaN propagates into the mean
  EXPECT_TRUE(std::isnan(a.variance()));  // and into the variance
  EXPECT_DOUBLE_EQ(a.variance_of_finite(), 7.0 / 3.0);
}

TEST(TallyNonfinite, InfinityPropagatesIntoTheMean) {
  Tally t;
  t.add(1.0, 0);
  t.add(std::numeric_limits<double>::infinity(), 1);
  EXPECT_EQ(t.mean(), std::numeric_limits<double>::infinity());
}

TEST(TallyLargest, KeepsTheLargestMagnitudes) {
  Tally t(40);
  for (int i = 0; i < 1000; ++i) t.add((i % 2 ? -1.0 : 1.0) * i, static_cast<std::uint64_t>(i));
  const std::vector<double> out = t.largest().sorted();
  ASSERT_EQ(out.size(), 40u);
  for (std::size_t k = 0; k < out.size(); ++k) EXPECT_EQ(out[k], 999.0 - static_cast<double>(k));
}

// The set kept is the k largest of everything seen, whatever the order of adds and merges.
TEST(TallyLargest, MergeKeepsTheLargestOfBothInAnyOrder) {
  Tally a(16), b(16), c(16);
  for (int i = 0; i < 100; ++i) a.add(i, static_cast<std::uint64_t>(i));
  for (int i = 100; i < 105; ++i) b.add(i, static_cast<std::uint64_t>(i));
  for (int i = 104; i >= 0; --i) c.add(i, static_cast<std::uint64_t>(i));
  a.merge(b);
  const std::vector<double> out = a.largest().sorted();
  ASSERT_EQ(out.size(), 16u);
  EXPECT_EQ(out[0], 104.0);
  EXPECT_EQ(out[15], 89.0);
  EXPECT_EQ(out, c.largest().sorted());
}

TEST(TallyEffectiveSamples, KishSizeAndNonzeroCount) {
  Tally equal, one_peak;
  for (int i = 0; i < 100; ++i) equal.add(i % 2 ? -3.0 : 3.0, static_cast<std::uint64_t>(i));
  for (int i = 0; i < 100; ++i) one_peak.add(i == 7 ? 1e6 : 0.0, static_cast<std::uint64_t>(i));
  EXPECT_DOUBLE_EQ(equal.effective_sample_size(), 100.0);
  EXPECT_EQ(equal.nonzero_count(), 100u);
  EXPECT_DOUBLE_EQ(one_peak.effective_sample_size(), 1.0);
  EXPECT_EQ(one_peak.nonzero_count(), 1u);
}

}  // namespace
}  // namespace pcbench
