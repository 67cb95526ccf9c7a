#include "harness/run/runner.h"

#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <bit>
#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "base/tally.h"
#include "harness/plan/plan.h"
#include "harness/verify/statistics.h"
#include "integrands/point_integrand.h"
#include "integrands/registry.h"
#include "tests/test_support.h"

namespace pcbench {
namespace {

RunResult run_with_threads(const RunPlan& p, int threads, std::uint64_t seed = 1) {
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  static_cast<std::size_t>(threads));
  return execute_run(p, {.seed = seed});
}

void expect_same_numbers(const RunResult& a, const RunResult& b) {
  ASSERT_EQ(a.replicates.size(), b.replicates.size());
  for (std::size_t r = 0; r < a.replicates.size(); ++r) {
    // Bitwise equality: the same floating-point operations in the same order.
    EXPECT_EQ(a.replicates[r].estimate, b.replicates[r].estimate) << "replicate " << r;
    EXPECT_EQ(a.replicates[r].variance, b.replicates[r].variance) << "replicate " << r;
    EXPECT_EQ(a.replicates[r].n, b.replicates[r].n);
    EXPECT_EQ(a.replicates[r].largest, b.replicates[r].largest);
    ASSERT_EQ(a.replicates[r].checkpoints.size(), b.replicates[r].checkpoints.size());
    for (std::size_t k = 0; k < a.replicates[r].checkpoints.size(); ++k) {
      EXPECT_EQ(a.replicates[r].checkpoints[k].estimate, b.replicates[r].checkpoints[k].estimate);
    }
  }
  EXPECT_EQ(a.counters.connections, b.counters.connections);
}

TEST(RunnerDeterminism, SameNumbersForAnyThreadCount) {
  // 100003 samples: several chunks per replicate and a ragged last batch.
  const RunPlan run_plan =
      plan_single("plain", "genz-gaussian", {{"light_dims", {"2"}}}, 100003, 6);
  const RunResult one = run_with_threads(run_plan, 1);
  const RunResult two = run_with_threads(run_plan, 2);
  const RunResult three = run_with_threads(run_plan, 3);
  ASSERT_EQ(one.status, RunStatus::kOk);
  expect_same_numbers(one, two);
  expect_same_numbers(one, three);

  // Probabilistic connections with a pool shared by each batch: draws, pools and the alias
  // tables all depend on the sample index only.
  const RunPlan shared =
      plan_single("pcbpt", "genz-oscillatory", {{"pool", {"shared"}}, {"M", {"64"}}}, 30001, 4);
  expect_same_numbers(run_with_threads(shared, 1), run_with_threads(shared, 2));
}

TEST(RunnerDeterminism, NumbersDoNotDependOnSuiteOrder) {
  GridRequest a{.estimators = {"plain"},
                .integrands = {"genz-gaussian"},
                .samples = 5000,
                .replicates = 3,
                .where = "a"};
  GridRequest b{.estimators = {"plain"},
                .integrands = {"genz-oscillatory"},
                .samples = 5000,
                .replicates = 3,
                .where = "b"};
  const auto forward = plan_runs({a, b}, {});
  const auto backward = plan_runs({b, a}, {});
  ASSERT_EQ(forward[0].id, backward[1].id);
  expect_same_numbers(execute_run(forward[0], {}), execute_run(backward[1], {}));
  expect_same_numbers(execute_run(forward[1], {}), execute_run(backward[0], {}));
}

TEST(RunnerDeterminism, SeedAndReplicateChangeTheNumbers) {
  const RunPlan run_plan = plan_single("plain", "genz-gaussian", {}, 2000, 2);
  const RunResult seed1 = execute_run(run_plan, {.seed = 1});
  const RunResult seed2 = execute_run(run_plan, {.seed = 2});
  EXPECT_NE(seed1.replicates[0].estimate, seed2.replicates[0].estimate);
  EXPECT_NE(seed1.replicates[0].estimate, seed1.replicates[1].estimate);
}

TEST(RunnerChunks, EverySampleIsCountedOnce) {
  for (std::uint64_t samples : {1ull, 255ull, 256ull, 4097ull, 300001ull}) {
    const RunPlan run_plan = plan_single("plain", "genz-gaussian", {}, samples, 2);
    const RunResult result = execute_run(run_plan, {});
    ASSERT_EQ(result.status, RunStatus::kOk);
    for (const ReplicateResult& rep : result.replicates) EXPECT_EQ(rep.n, samples);
    EXPECT_EQ(result.counters.camera_paths, 2 * samples);
    EXPECT_EQ(result.counters.connections, 2 * samples);
  }
}

TEST(RunnerChunks, ChunkSizeDependsOnlyOnTheSampleCount) {
  EXPECT_EQ(chunk_size(1), 16 * kBatchSize);
  EXPECT_EQ(chunk_size(100000) % kBatchSize, 0u);
  EXPECT_LE((100000000 + chunk_size(100000000) - 1) / chunk_size(100000000), 64u);
}

TEST(RunnerNonfinite, CountedLocatedAndTheRunMarkedInvalid) {
  // f is infinite for x0 < 0.01: about 1% of the samples.
  const RunPlan run_plan =
      plan_single("plain", "expr", {{"f", {"x0 < 0.01 ? 1/0 : x0"}}, {"exact", {"0.5"}}}, 1000, 3);
  const RunResult result = execute_run(run_plan, {.seed = 9});
  EXPECT_EQ(result.status, RunStatus::kInvalid);
  ASSERT_TRUE(result.first_nonfinite.has_value());
  EXPECT_EQ(result.first_nonfinite->seed, 9u);
  const ReplicateResult& rep = result.replicates[result.first_nonfinite->replicate];
  EXPECT_GT(rep.nonfinite, 0u);
  EXPECT_EQ(rep.n, 1000u);  // non-finite samples are counted, not dropped
  EXPECT_FALSE(std::isfinite(rep.estimate));
  EXPECT_NE(result.error.find("replicate"), std::string::npos);
}

// The runner's fast path (Estimator::tally_batch: plain and vc-all on fresh pools, one fused
// loop in the workspace) against the generic path (estimate_batch, then the runner's tally).

std::uint64_t bits(double x) {
  return std::bit_cast<std::uint64_t>(x);
}

void expect_same_tally(const Tally& a, const Tally& b, const std::string& where) {
  EXPECT_EQ(a.count(), b.count()) << where;
  EXPECT_EQ(a.nonfinite_count(), b.nonfinite_count()) << where;
  EXPECT_EQ(a.first_nonfinite_sample(), b.first_nonfinite_sample()) << where;
  EXPECT_EQ(bits(a.sum()), bits(b.sum())) << where;
  EXPECT_EQ(bits(a.mean()), bits(b.mean())) << where;
  EXPECT_EQ(bits(a.variance_of_finite()), bits(b.variance_of_finite())) << where;
  EXPECT_EQ(a.largest().sorted(), b.largest().sorted()) << where;
  EXPECT_EQ(a.nonzero_count(), b.nonzero_count()) << where;
  EXPECT_EQ(bits(a.effective_sample_size()), bits(b.effective_sample_size())) << where;
  EXPECT_EQ(bits(a.sum_of_squares()), bits(b.sum_of_squares())) << where;
}

// Each sample's estimate and magnitude from the fast path, alone (a tally of that one sample,
// whose sum is the sample: 0 + x = x, and no estimate is -0), equal the generic path's bit for
// bit; and a whole batch tallied by the fast path is the batch's estimates tallied in order, with
// the same work counted. Returns how many of the estimates compared were not finite, and 0.
std::pair<std::uint64_t, std::uint64_t> expect_fast_path_matches(const RunPlan& plan,
                                                                 const std::string& name) {
  const Estimator& estimator = *plan.made_estimator;
  const auto generic_paths = plan.made_integrand->make_workspace();
  const auto fast_paths = plan.made_integrand->make_workspace();
  EstimatorScratch scratch;
  std::uint64_t nonfinite = 0, zeros = 0;
  for (const auto& [first, count] : {std::pair<std::uint32_t, std::uint32_t>{0, kBatchSize},
                                     {5 * kBatchSize, kBatchSize},
                                     {9 * kBatchSize, 77}}) {
    const std::string where = name + " batch at " + std::to_string(first);
    Counters generic_counters, fast_counters;
    std::vector<double> estimates(count), magnitudes(count);
    BatchContext ctx{.key = run_key(5, plan.stream_hash),
                     .replicate = 3,
                     .first_sample = first,
                     .sample_count = count,
                     .counters = &generic_counters};
    ctx.magnitudes = magnitudes;
    estimator.estimate_batch(ctx, *generic_paths, scratch, estimates);
    Tally generic(257), fast(257);
    CompensatedSum generic_magnitude, fast_magnitude;
    for (std::uint32_t i = 0; i < count; ++i) {
      generic.add(estimates[i], first + i);
      generic_magnitude.add(magnitudes[i]);
    }
    BatchContext fast_ctx = ctx;
    fast_ctx.magnitudes = {};
    fast_ctx.counters = &fast_counters;
    EXPECT_TRUE(estimator.tally_batch(fast_ctx, *fast_paths, fast, fast_magnitude)) << where;
    expect_same_tally(generic, fast, where);
    EXPECT_EQ(bits(generic_magnitude.value()), bits(fast_magnitude.value())) << where;
    EXPECT_EQ(generic_counters.camera_paths, fast_counters.camera_paths) << where;
    EXPECT_EQ(generic_counters.light_paths, fast_counters.light_paths) << where;
    EXPECT_EQ(generic_counters.connections, fast_counters.connections) << where;
    EXPECT_EQ(generic_counters.importance_evaluations, fast_counters.importance_evaluations);

    for (std::uint32_t i = 0; i < count; ++i) {
      BatchContext one = fast_ctx;
      one.first_sample = first + i;
      one.sample_count = 1;
      Tally sample;
      CompensatedSum magnitude;
      EXPECT_TRUE(estimator.tally_batch(one, *fast_paths, sample, magnitude));
      EXPECT_EQ(bits(sample.sum()), bits(estimates[i])) << where << ", sample " << i;
      // A one-term compensated sum is the term itself when finite (an infinite one gives NaN,
      // inf - inf in the compensation, which the run's sum of magnitudes gives too).
      CompensatedSum generic_one;
      generic_one.add(magnitudes[i]);
      EXPECT_EQ(bits(magnitude.value()), bits(generic_one.value())) << where << ", sample " << i;
      if (std::isfinite(magnitudes[i])) {
        EXPECT_EQ(bits(magnitude.value()), bits(magnitudes[i]));
      }
      nonfinite += std::isfinite(estimates[i]) ? 0 : 1;
      zeros += estimates[i] == 0.0 ? 1 : 0;
    }
  }
  return {nonfinite, zeros};
}

TEST(RunnerFastPath, PerSampleValuesEqualTheGenericPath) {
  // Every analytic integrand at its defaults (discontinuities: blocker, door, door-2d,
  // genz-discontinuous, sparse-support; zero regions; singular values; non-uniform densities),
  // more dimensions, and an expression with zeros, infinities and NaNs.
  std::vector<std::pair<std::string, std::map<std::string, std::vector<std::string>>>> cases;
  for (const IntegrandEntry& entry : integrand_registry()) {
    if (entry.name != "expr") cases.push_back({entry.name, {}});
  }
  cases.push_back({"genz-gaussian", {{"light_dims", {"2"}}, {"camera_dims", {"3"}}}});
  cases.push_back({"genz-discontinuous", {{"light_dims", {"3"}}, {"camera_dims", {"2"}}}});
  const std::string wild = "x0 < 0.3 ? 0 : (y0 < 0.02 ? 1/0 : (y0 > 0.98 ? 0/0 : (x0 - 0.6) * y0))";
  cases.push_back({"expr", {{"f", {wild}}, {"exact", {"0"}}}});
  for (const auto& [integrand, params] : cases) {
    for (const auto& [estimator, estimator_params] :
         std::vector<std::pair<std::string, std::map<std::string, std::vector<std::string>>>>{
             {"plain", {}}, {"vc-all", {}}, {"vc-all", {{"M", {"3"}}}}}) {
      auto all = params;
      all.insert(estimator_params.begin(), estimator_params.end());
      const RunPlan plan = plan_single(estimator, integrand, all, 1000, 2);
      const auto [nonfinite, zeros] =
          expect_fast_path_matches(plan, estimator + " on " + integrand + " (" +
                                             std::to_string(all.size()) + " parameters)");
      if (integrand == "expr") {
        // The expression's estimates include all three kinds, so they were all compared.
        EXPECT_GT(nonfinite, 0u);
        EXPECT_TRUE(estimator != "plain" || zeros > 0);  // a pool of one: zero 30% of the time
      }
    }
  }
}

TEST(RunnerFastPath, OnlyEstimatorsThatConnectEveryPathOfAFreshPool) {
  for (const auto& [estimator, params, expected] :
       std::vector<std::tuple<std::string, std::map<std::string, std::vector<std::string>>, bool>>{
           {"plain", {}, true},
           {"vc-all", {}, true},
           {"vc-all", {{"pool", {"shared"}}}, false},
           {"lvc", {}, false},
           {"pcbpt", {}, false}}) {
    const RunPlan plan = plan_single(estimator, "genz-gaussian", params, 1000, 2);
    const auto paths = plan.made_integrand->make_workspace();
    Counters counters;
    Tally tally;
    CompensatedSum magnitudes;
    const BatchContext ctx{.key = 1, .sample_count = 16, .counters = &counters};
    EXPECT_EQ(plan.made_estimator->tally_batch(ctx, *paths, tally, magnitudes), expected)
        << estimator;
    EXPECT_EQ(tally.count(), expected ? 16u : 0u) << estimator;
  }
}

// An estimator without the fast path: forwards everything else.
class GenericOnly final : public Estimator {
 public:
  explicit GenericOnly(std::shared_ptr<const Estimator> inner) : inner_(std::move(inner)) {}
  void estimate_batch(const BatchContext& ctx, PathWorkspace& paths, EstimatorScratch& scratch,
                      std::span<double> estimates) const override {
    inner_->estimate_batch(ctx, paths, scratch, estimates);
  }
  bool samples_independent() const override { return inner_->samples_independent(); }

 private:
  std::shared_ptr<const Estimator> inner_;
};

TEST(RunnerFastPath, RunsEqualTheGenericRunBitForBit) {
  for (const auto& [estimator, integrand] : std::vector<std::pair<std::string, std::string>>{
           {"plain", "genz-gaussian"}, {"plain", "door"}, {"vc-all", "genz-discontinuous"}}) {
    // A ragged last chunk and batch; checkpoints inside chunks.
    const RunPlan fast = plan_single(estimator, integrand, {}, 70001, 3);
    RunPlan generic = fast;
    generic.made_estimator = std::make_shared<GenericOnly>(fast.made_estimator);
    const RunResult a = run_with_threads(fast, 2, 7);
    const RunResult b = run_with_threads(generic, 2, 7);
    ASSERT_EQ(a.status, RunStatus::kOk);
    expect_same_numbers(a, b);
    EXPECT_EQ(a.counters.camera_paths, b.counters.camera_paths);
    EXPECT_EQ(a.counters.light_paths, b.counters.light_paths);
    for (std::size_t r = 0; r < a.replicates.size(); ++r) {
      const ReplicateResult& x = a.replicates[r];
      const ReplicateResult& y = b.replicates[r];
      EXPECT_EQ(bits(x.mean_abs), bits(y.mean_abs));
      EXPECT_EQ(x.nonzero, y.nonzero);
      EXPECT_EQ(bits(x.effective_samples), bits(y.effective_samples));
      EXPECT_EQ(bits(x.largest_square_share), bits(y.largest_square_share));
    }
  }
}

// A model that fails inside a run, as a buggy user integrand would.
struct ThrowingModel {
  int light_dims() const { return 1; }
  int camera_dims() const { return 1; }
  Reference reference() const { return {.value = 0.5, .kind = ReferenceKind::kExact}; }
  double f(const double* x, const double*) const {
    if (x[0] > 0.999) throw std::runtime_error("integrand exploded");
    return x[0];
  }
};

TEST(RunnerErrors, AnExceptionInsideARunIsRecordedInThatRun) {
  RunPlan p = plan_single("plain", "genz-gaussian", {}, 10000, 2);
  p.made_integrand = std::make_shared<PointIntegrand<ThrowingModel>>(ThrowingModel{});
  const RunResult result = execute_run(p, {});
  EXPECT_EQ(result.status, RunStatus::kError);
  EXPECT_EQ(result.error, "integrand exploded");
}

TEST(RunnerInterrupt, AnInterruptedRunIsMarkedNotRun) {
  const RunPlan run_plan = plan_single("plain", "genz-gaussian", {}, 10000, 2);
  const std::atomic<bool> interrupted{true};
  const RunResult result = execute_run(run_plan, {.interrupted = &interrupted});
  EXPECT_EQ(result.status, RunStatus::kNotRun);
}

// ∫_0^1 exp(-k (t - c)²) dt in closed form.
double gaussian_1d(double k, double c) {
  const double s = std::sqrt(k);
  return std::sqrt(M_PI) / (2.0 * s) * (std::erf(s * (1.0 - c)) + std::erf(s * c));
}

// plain's variance on genz-gaussian is known exactly: Var f = ∫ f² - I², and f² is the Gaussian
// with twice the exponent. The across-replicate variance must match it: s² / (σ²/N) is
// χ²(R-1) when the samples are independent. Correlated streams (a shared or overlapping stream)
// keep the mean right but break this. False-alarm budget: 1e-4 two-sided, fixed seed.
// The convergence series: checkpoints at powers of two from 1024 and at N; each is the running
// mean of the first n samples (checked against a run of n samples: the same streams), and the
// last is the replicate's estimate.
TEST(RunnerSeries, CheckpointsAreRunningMeansOfThePrefix) {
  EXPECT_EQ(series_checkpoints(5000), (std::vector<std::uint64_t>{1024, 2048, 4096, 5000}));
  EXPECT_EQ(series_checkpoints(1000), (std::vector<std::uint64_t>{1000}));
  const RunPlan whole = plan_single("plain", "genz-gaussian", {}, 70000, 3);
  const RunResult result = execute_run(whole, {.seed = 4});
  for (const ReplicateResult& rep : result.replicates) {
    ASSERT_EQ(rep.checkpoints.size(), 8u);  // 1024 .. 65536, 70000
    EXPECT_EQ(rep.checkpoints.back().samples, 70000u);
    EXPECT_NEAR(rep.checkpoints.back().estimate, rep.estimate, 1e-15);
    for (std::size_t k = 1; k < rep.checkpoints.size(); ++k) {
      EXPECT_GE(rep.checkpoints[k].cpu_seconds, rep.checkpoints[k - 1].cpu_seconds);
    }
  }
  // The checkpoint at 16384 is the estimate of a run of 16384 samples with the same random
  // streams (the plan keeps its id, so the streams are the same; only the budget differs).
  RunPlan prefix = whole;
  prefix.samples = 16384;
  const RunResult shorter = execute_run(prefix, {.seed = 4});
  for (std::size_t r = 0; r < result.replicates.size(); ++r) {
    EXPECT_NEAR(result.replicates[r].checkpoints[4].estimate, shorter.replicates[r].estimate,
                1e-15);
  }
  const Aggregates a = aggregate(result.replicates, result.reference, whole.samples);
  ASSERT_EQ(a.series.size(), 8u);
  EXPECT_DOUBLE_EQ(a.series.back().mean, a.mean);
  EXPECT_TRUE(std::isfinite(a.rmse_slope));
  EXPECT_LT(a.efficiency_low, a.efficiency);
  EXPECT_GT(a.efficiency_high, a.efficiency);
}

TEST(PlainVariance, MatchesTheExactVarianceOfTheGaussian) {
  constexpr double kSharpness = 4.0, kCenter = 0.3;
  constexpr int kDims = 3;  // light_dims 2 + camera_dims 1
  constexpr std::uint64_t kSamples = 20000;
  constexpr std::uint32_t kReplicates = 64;
  const RunPlan run_plan = plan_single(
      "plain", "genz-gaussian", {{"light_dims", {"2"}}, {"sharpness", {"4"}}, {"center", {"0.3"}}},
      kSamples, kReplicates);
  const RunResult result = execute_run(run_plan, {.seed = 3});
  const double integral = std::pow(gaussian_1d(kSharpness * kSharpness, kCenter), kDims);
  const double second_moment = std::pow(gaussian_1d(2 * kSharpness * kSharpness, kCenter), kDims);
  const double sigma2 = second_moment - integral * integral;

  Tally spread;
  for (std::size_t r = 0; r < result.replicates.size(); ++r) {
    spread.add(result.replicates[r].estimate, r);
  }
  const double statistic = (kReplicates - 1) * spread.variance() / (sigma2 / kSamples);
  const boost::math::chi_squared chi2(kReplicates - 1);
  const double p = 2 * std::min(boost::math::cdf(chi2, statistic),
                                boost::math::cdf(boost::math::complement(chi2, statistic)));
  EXPECT_GT(p, 1e-4) << "across-replicate variance " << spread.variance() * kSamples << " vs exact "
                     << sigma2;

  // The within-replicate variance estimates the same σ² (samples are independent here).
  Tally within;
  for (std::size_t r = 0; r < result.replicates.size(); ++r) {
    within.add(result.replicates[r].variance, r);
  }
  const double z = (within.mean() - sigma2) / std::sqrt(within.variance() / kReplicates);
  EXPECT_LT(std::fabs(z), 4.5);  // two-sided normal tail 7e-6

  // And the mean is unbiased: Student t at the same budget.
  const Verdict v = test_against_reference(result, "consistent");
  EXPECT_NEAR(result.reference.value, integral, 1e-15);
  EXPECT_GT(v.p_value, 1e-4);
}

}  // namespace
}  // namespace pcbench
