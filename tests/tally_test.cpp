#include "base/tally.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
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

// The k kept are the k largest of everything added (a sort of all of them says which), for
// capacities from 1, with ties at the cut, zeros, infinities, values spread over many decades and
// values that share all but their lowest bits (the selection goes down to the last bit), added
// one at a time and through add_each.
TEST(TallyLargest, KeepsExactlyTheLargestOfAnyValues) {
  std::mt19937_64 engine(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const std::vector<std::function<double()>> kinds = {
      [&] { return unit(engine); },
      [&] { return std::floor(unit(engine) * 5.0); },  // many ties, zeros
      [&] { return std::pow(10.0, 600.0 * unit(engine) - 300.0); },
      [&] { return 1.0 + std::ldexp(std::floor(unit(engine) * 16.0), -52); },  // last bits only
      [&] {
        const double u = unit(engine);
        return u < 0.01 ? std::numeric_limits<double>::infinity() : u < 0.5 ? 0.0 : u;
      },
      [&] { return 3.0; }};
  for (std::size_t kind = 0; kind < kinds.size(); ++kind) {
    for (const std::size_t capacity : {1u, 2u, 3u, 16u, 257u}) {
      for (const int n : {1, 5, 700, 5000}) {
        std::vector<double> xs(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) xs[i] = (i % 3 == 0 ? -1.0 : 1.0) * kinds[kind]();
        Tally one_by_one(capacity), each(capacity);
        for (int i = 0; i < n; ++i) one_by_one.add(xs[i], static_cast<std::uint64_t>(i));
        std::size_t next = 0;
        each.add_each(0, xs.size(), [&] { return xs[next++]; });

        std::vector<double> expected;
        for (const double x : xs) {
          if (std::isfinite(x)) expected.push_back(std::fabs(x));
        }
        std::sort(expected.begin(), expected.end(), std::greater<>());
        if (expected.size() > capacity) expected.resize(capacity);
        const std::string where = fmt::format("kind {}, capacity {}, n {}", kind, capacity, n);
        EXPECT_EQ(one_by_one.largest().sorted(), expected) << where;
        // add_each is add, one value after the other.
        EXPECT_EQ(each.largest().sorted(), expected) << where;
        EXPECT_EQ(std::bit_cast<std::uint64_t>(each.sum()),
                  std::bit_cast<std::uint64_t>(one_by_one.sum()))
            << where;
        EXPECT_EQ(std::bit_cast<std::uint64_t>(each.variance_of_finite()),
                  std::bit_cast<std::uint64_t>(one_by_one.variance_of_finite()))
            << where;
        EXPECT_EQ(each.count(), one_by_one.count()) << where;
        EXPECT_EQ(each.nonfinite_count(), one_by_one.nonfinite_count()) << where;
        EXPECT_EQ(each.first_nonfinite_sample(), one_by_one.first_nonfinite_sample()) << where;
        EXPECT_EQ(each.nonzero_count(), one_by_one.nonzero_count()) << where;
        EXPECT_EQ(std::bit_cast<std::uint64_t>(each.effective_sample_size()),
                  std::bit_cast<std::uint64_t>(one_by_one.effective_sample_size()))
            << where;
      }
    }
  }
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
