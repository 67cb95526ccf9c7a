// Do the standard errors mean what they say? Student-t intervals from the replicates of many
// independent runs must cover the exact value at their nominal rate; correlated random streams
// or a wrong stderr formula would show here even where the mean is right.
#include <gtest/gtest.h>

#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>

#include "harness/plan/plan.h"
#include "harness/run/runner.h"
#include "harness/verify/statistics.h"
#include "tests/test_support.h"

namespace pcbench {
namespace {

// Student t intervals from `runs` independent runs of 8 replicates; the number that cover the
// exact value is Binomial(runs, 0.95) if the intervals are right. Returns that count and the
// band that holds 1 - 1e-4 of its distribution.
struct Coverage {
  int covered;
  double low, high;
};

Coverage coverage(const RunPlan& plan, int runs) {
  const double t = boost::math::quantile(boost::math::students_t(plan.replicates - 1), 0.975);
  int covered = 0;
  for (int run = 0; run < runs; ++run) {
    const RunResult result = execute_run(plan, {.seed = 1000u + static_cast<std::uint64_t>(run)});
    const Aggregates a = aggregate(result.replicates, result.reference, plan.samples);
    if (std::fabs(a.bias) <= t * a.stderr_of_mean) ++covered;
  }
  const boost::math::binomial expected(runs, 0.95);
  return {covered, boost::math::quantile(expected, 0.5e-4),
          boost::math::quantile(boost::math::complement(expected, 0.5e-4))};
}

TEST(PlainCoverage, StudentIntervalsCoverAtTheirNominalRate) {
  const RunPlan plan =
      plan_single("plain", "genz-gaussian", {{"light_dims", {"2"}}, {"center", {"0.4"}}}, 2000, 8);
  const Coverage c = coverage(plan, 1000);
  EXPECT_GE(c.covered, c.low);
  EXPECT_LE(c.covered, c.high);
}

// The same for pool-based estimators, including a pool shared by the samples of a batch: the
// replicates stay independent, so the intervals must still hold.
TEST(ResamplingCoverage, StudentIntervalsCoverForPoolsFreshAndShared) {
  const std::vector<RunPlan> plans = {
      plan_single("vc-all", "blocker", {{"M", {"8"}}}, 1000, 8),
      plan_single("pcbpt", "genz-oscillatory", {{"M", {"16"}}, {"K", {"2"}}, {"pool", {"shared"}}},
                  1024, 8)};
  for (const RunPlan& plan : plans) {
    const Coverage c = coverage(plan, 400);
    EXPECT_GE(c.covered, c.low) << plan.estimator->name;
    EXPECT_LE(c.covered, c.high) << plan.estimator->name;
  }
}

// A long run, 64 replicates × 10^7 samples, that would show a small bias a short run cannot
// (e.g. from a generator that loses low bits). False-alarm budget 1e-4. Label: full.
TEST(FullPlainUnbiased, LongRunOnTheOscillatoryFamily) {
  const RunPlan plan = plan_single(
      "plain", "genz-oscillatory",
      {{"light_dims", {"3"}}, {"camera_dims", {"2"}}, {"center", {"0.1"}}}, 10000000, 64);
  const RunResult result = execute_run(plan, {.seed = 4242});
  ASSERT_EQ(result.status, RunStatus::kOk);
  Verdict v = test_against_reference(result, "consistent");
  std::vector<Verdict*> family = {&v};
  decide_family(family, 1e-4);
  EXPECT_EQ(v.result, "consistent") << v.reason;
  // What this budget can see, for the record (about 0.4% of this small integral).
  RecordProperty("min_detectable_rel_bias", std::to_string(v.min_detectable_rel_bias));
}

}  // namespace
}  // namespace pcbench
