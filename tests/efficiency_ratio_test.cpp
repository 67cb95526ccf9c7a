// The efficiency ratio and its interval (harness/verify/efficiency_ratio.h): the point value is the
// formula's, and the interval covers the true ratio at least at its stated level.
#include "harness/verify/efficiency_ratio.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace pcbench {
namespace {

TEST(EfficiencyRatio, PointValueIsTheVarianceTimesCostRatio) {
  const std::vector<double> a = {1.0, 3.0, 2.0, 4.0};  // variance 5/3
  const std::vector<double> b = {2.0, 2.5, 1.5, 2.0};  // variance 1/6
  const std::vector<double> cost_a = {1.0, 1.0, 1.0, 1.0};
  const std::vector<double> cost_b = {4.0, 4.0, 4.0, 4.0};  // b costs 4x
  const EfficiencyRatio e = efficiency_ratio(a, cost_a, b, cost_b);
  ASSERT_TRUE(e.valid);
  EXPECT_NEAR(e.variance_ratio, 10.0, 1e-12);
  EXPECT_NEAR(e.cost_ratio, 0.25, 1e-12);
  EXPECT_NEAR(e.ratio, 2.5, 1e-12);
  EXPECT_LT(e.low, e.ratio);
  EXPECT_GT(e.high, e.ratio);
  EXPECT_EQ(e.pairs, 4u);
}

TEST(EfficiencyRatio, InvalidWithoutSpreadOrReplicates) {
  const std::vector<double> one = {1.0};
  const std::vector<double> flat = {2.0, 2.0, 2.0};
  const std::vector<double> spread = {1.0, 2.0, 3.0};
  const std::vector<double> cost = {1.0, 1.0, 1.0};
  EXPECT_FALSE(efficiency_ratio(one, one, spread, cost).valid);
  EXPECT_FALSE(efficiency_ratio(flat, cost, spread, cost).valid);
  const std::vector<double> no_time = {1.0, 0.0, 1.0};
  EXPECT_FALSE(efficiency_ratio(spread, no_time, spread, cost).valid);
}

// Coverage: normal replicate estimates with σ_a = 2 σ_b and log-normal paired costs sharing a
// per-pair machine-load factor, b 3x dearer: the true ratio is 4 / 3. Over 2000 trials (R = 8,
// fixed seed) the 95% interval (Bonferroni over two 97.5% factors, so ~97.5% or more) must cover
// it in at least 93%: a coverage of 95% or more falls below that with probability < 1e-4.
TEST(EfficiencyRatio, IntervalCoversTheTrueRatio) {
  std::mt19937_64 rng(20261201);
  std::normal_distribution<double> normal;
  constexpr int kTrials = 2000;
  constexpr int kReplicates = 8;
  const double truth = 4.0 / 3.0;
  int covered = 0;
  for (int t = 0; t < kTrials; ++t) {
    std::vector<double> a, b, cost_a, cost_b;
    for (int r = 0; r < kReplicates; ++r) {
      a.push_back(10.0 + 2.0 * normal(rng));
      b.push_back(10.0 + 1.0 * normal(rng));
      const double load = std::exp(0.3 * normal(rng));  // what the machine did at the time
      cost_a.push_back(load * std::exp(0.05 * normal(rng)));
      cost_b.push_back(3.0 * load * std::exp(0.05 * normal(rng)));
    }
    const EfficiencyRatio e = efficiency_ratio(a, cost_a, b, cost_b);
    ASSERT_TRUE(e.valid);
    if (e.low <= truth && truth <= e.high) ++covered;
  }
  EXPECT_GE(covered, static_cast<int>(0.93 * kTrials)) << covered << " of " << kTrials;
}

}  // namespace
}  // namespace pcbench
