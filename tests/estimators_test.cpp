#include "estimators/registry.h"

#include <gtest/gtest.h>

#include <boost/math/distributions/chi_squared.hpp>

#include "base/discrete_sampler.h"
#include "base/rng.h"
#include "estimators/resampling.h"
#include "harness/plan/plan.h"
#include "harness/run/runner.h"
#include "harness/verify/statistics.h"
#include "integrands/point_integrand.h"
#include "integrands/registry.h"
#include "tests/test_support.h"

namespace pcbench {
namespace {

// f = x0 + 10 y0 with uniform sampling: plain's estimate must be f at the sampled points, and
// the light and camera points must come from their own streams.
struct LinearModel {
  int light_dims() const { return 1; }
  int camera_dims() const { return 1; }
  Reference reference() const { return {.value = 5.5, .kind = ReferenceKind::kExact}; }
  double f(const double* x, const double* y) const { return x[0] + 10.0 * y[0]; }
};

TEST(PlainEstimator, EstimateIsFOverThePdfsOfItsOwnStreams) {
  const PointIntegrand<LinearModel> integrand{LinearModel{}};
  auto workspace = integrand.make_workspace();
  EstimatorScratch scratch;
  Counters counters;
  std::vector<ResamplingRecord> log;
  std::vector<double> estimates(5);
  const BatchContext ctx{.key = 99,
                         .replicate = 2,
                         .first_sample = 40,
                         .sample_count = 5,
                         .counters = &counters,
                         .log = &log};
  find_estimator("plain").make({})->estimate_batch(ctx, *workspace, scratch, estimates);

  for (std::uint32_t i = 0; i < 5; ++i) {
    const double x =
        RandomStream(
            {.key = 99, .replicate = 2, .purpose = StreamPurpose::kLightPool, .sample = 40 + i})
            .uniform();
    const double y =
        RandomStream(
            {.key = 99, .replicate = 2, .purpose = StreamPurpose::kCameraPath, .sample = 40 + i})
            .uniform();
    EXPECT_EQ(estimates[i], x + 10.0 * y);
  }
  EXPECT_EQ(counters.connections, 5u);
  EXPECT_EQ(counters.light_paths, 5u);
  // The resampling step, as made: a pool of one, drawn once with probability 1.
  ASSERT_EQ(log.size(), 5u);
  EXPECT_EQ(log[3].sample, 43u);
  EXPECT_EQ(log[3].pmf, std::vector<double>{1.0});
  EXPECT_EQ(log[3].draws, std::vector<std::uint32_t>{0});
}

}  // namespace
}  // namespace pcbench

namespace pcbench {
namespace {

// Runs one batch of `estimator` on `integrand` and returns its estimates and log.
struct BatchOutput {
  std::vector<double> estimates;
  std::vector<ResamplingRecord> log;
  Counters counters;
};

BatchOutput run_batch(const Estimator& estimator, const Integrand& integrand,
                      std::uint32_t first_sample, std::uint32_t count) {
  BatchOutput out;
  auto workspace = integrand.make_workspace();
  EstimatorScratch scratch;
  out.estimates.resize(count);
  const BatchContext ctx{.key = 1234,
                         .replicate = 1,
                         .first_sample = first_sample,
                         .sample_count = count,
                         .counters = &out.counters,
                         .log = &out.log};
  estimator.estimate_batch(ctx, *workspace, scratch, out.estimates);
  return out;
}

std::unique_ptr<Estimator> make(const std::string& name, const ParamText& params) {
  const EstimatorEntry& entry = find_estimator(name);
  return entry.make(resolve_params(entry.params, params, name));
}

std::unique_ptr<Integrand> make_integrand(const std::string& name, const ParamText& params) {
  const IntegrandEntry& entry = find_integrand(name);
  return entry.make(resolve_params(entry.params, params, name));
}

// With P ∝ f exactly (importance=f, no uniform mixing) on a positive integrand, every draw has
// f / P = Σ_j f_j: probabilistic connections then reproduce vertex connection to the whole pool
// sample by sample, whatever the draws. A wrong weight or normalisation breaks the equality.
TEST(ResamplingWeights, IdealImportanceReproducesVertexConnection) {
  const auto integrand = make_integrand("genz-gaussian", {{"light_dims", "2"}});
  for (const char* pool : {"fresh", "shared"}) {
    for (const char* sampler : {"alias", "cdf"}) {
      const auto pcbpt = make("pcbpt", {{"M", "8"},
                                        {"K", "3"},
                                        {"importance", "f"},
                                        {"uniform_mix", "0"},
                                        {"pool", pool},
                                        {"sampler", sampler}});
      const auto vc_all = make("vc-all", {{"M", "8"}, {"pool", pool}});
      const BatchOutput a = run_batch(*pcbpt, *integrand, 512, 100);
      const BatchOutput b = run_batch(*vc_all, *integrand, 512, 100);
      for (std::size_t i = 0; i < a.estimates.size(); ++i) {
        EXPECT_NEAR(a.estimates[i], b.estimates[i], 1e-12 * b.estimates[i])
            << pool << " " << sampler << " sample " << i;
      }
    }
  }
}

TEST(ResamplingLog, RecordsAProperPmfAndTheDraws) {
  const auto integrand = make_integrand("genz-oscillatory", {});
  const auto pcbpt = make("pcbpt", {{"M", "10"}, {"K", "5"}, {"uniform_mix", "0.2"}});
  const BatchOutput out = run_batch(*pcbpt, *integrand, 0, 50);
  ASSERT_EQ(out.log.size(), 50u);
  for (const ResamplingRecord& record : out.log) {
    ASSERT_EQ(record.pmf.size(), 10u);
    double total = 0.0;
    for (double p : record.pmf) {
      EXPECT_GE(p, 0.2 / 10 * (1 - 1e-12));  // the uniform share keeps P > 0 everywhere
      total += p;
    }
    EXPECT_NEAR(total, 1.0, 1e-12);
    ASSERT_EQ(record.draws.size(), 5u);
    for (std::uint32_t d : record.draws) EXPECT_LT(d, 10u);
  }
  EXPECT_EQ(out.counters.importance_evaluations, 500u);
  EXPECT_EQ(out.counters.connections, 250u);
  EXPECT_EQ(out.counters.light_paths, 500u);

  const auto vc_all = make("vc-all", {{"M", "6"}});
  const BatchOutput all = run_batch(*vc_all, *integrand, 0, 3);
  EXPECT_EQ(all.log[2].draws, (std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5}));
}

TEST(ResamplingPools, SharedPoolIsOnePoolPerBatch) {
  const auto integrand = make_integrand("genz-gaussian", {});
  const auto shared = make("lvc", {{"M", "32"}, {"K", "2"}, {"pool", "shared"}});
  const BatchOutput out = run_batch(*shared, *integrand, 256, 200);
  EXPECT_EQ(out.counters.light_paths, 32u);
  EXPECT_FALSE(shared->samples_independent());
  EXPECT_TRUE(make("lvc", {})->samples_independent());
}

// Draw frequencies of both samplers follow the PMF (chi-square, budget 1e-6 each, fixed seed),
// including entries of probability zero, which must never be drawn.
TEST(ResamplingSampler, DrawsFollowThePmf) {
  const std::vector<double> pmf = {0.05, 0.0, 0.3, 0.15, 0.0, 0.25, 0.05, 0.2};
  for (const DiscreteSamplerKind kind : {DiscreteSamplerKind::kAlias, DiscreteSamplerKind::kCdf}) {
    DiscreteSampler sampler;
    sampler.build(pmf, kind);
    RandomStream rng({.key = 31});
    constexpr int kDraws = 200000;
    std::vector<double> counts(pmf.size(), 0.0);
    for (int i = 0; i < kDraws; ++i) counts[sampler.draw(rng)] += 1.0;
    EXPECT_EQ(counts[1], 0.0);
    EXPECT_EQ(counts[4], 0.0);
    double statistic = 0.0;
    int cells = 0;
    for (std::size_t j = 0; j < pmf.size(); ++j) {
      if (pmf[j] == 0.0) continue;
      const double expected = pmf[j] * kDraws;
      statistic += (counts[j] - expected) * (counts[j] - expected) / expected;
      ++cells;
    }
    const boost::math::chi_squared chi2(cells - 1);
    EXPECT_GT(boost::math::cdf(boost::math::complement(chi2, statistic)), 1e-6);
  }
}

// The alias table is Vose's pairing, column for column: against the textbook form (work lists as
// vectors, the under-full column popped from the back and paired with the last over-full one),
// every pick over a fine grid of u and every implied probability are the same to the bit, for
// pools with zeros, ties and heavy tails. pcbpt's draws, and so its images, depend on the exact
// table (ctest estimators.hashes checks them whole).
TEST(ResamplingSampler, AliasTableIsVosesPairing) {
  struct Column {
    double threshold;
    std::uint32_t alias;
  };
  auto textbook = [](const std::vector<double>& pmf) {
    const auto m = static_cast<std::uint32_t>(pmf.size());
    double total = 0.0;
    for (double p : pmf) total += p;
    std::vector<Column> columns(m);
    std::vector<std::uint32_t> small, large;
    for (std::uint32_t i = 0; i < m; ++i) {
      columns[i] = {pmf[i] * (static_cast<double>(m) / total), i};
      (columns[i].threshold < 1.0 ? small : large).push_back(i);
    }
    while (!small.empty() && !large.empty()) {
      const std::uint32_t s = small.back();
      small.pop_back();
      const std::uint32_t l = large.back();
      columns[l].threshold -= 1.0 - columns[s].threshold;
      columns[s].alias = l;
      if (columns[l].threshold < 1.0) {
        large.pop_back();
        small.push_back(l);
      }
    }
    for (std::uint32_t i : small) columns[i].threshold = 1.0;
    for (std::uint32_t i : large) columns[i].threshold = 1.0;
    return columns;
  };
  RandomStream rng({.key = 0xa11a5});
  for (const std::uint32_t m : {1u, 2u, 7u, 64u, 1000u}) {
    for (int shape = 0; shape < 3; ++shape) {
      std::vector<double> pmf(m);
      for (double& p : pmf) {
        const double u = rng.uniform();
        p = shape == 0 ? u : shape == 1 ? (u < 0.3 ? 0.0 : 0.5) : 1.0 / (1e-6 + u * u * u);
      }
      if (shape == 1) pmf[0] = 1.0;  // at least one nonzero
      DiscreteSampler sampler;
      sampler.build(pmf, DiscreteSamplerKind::kAlias);
      const std::vector<Column> want = textbook(pmf);
      std::vector<double> implied(m, 0.0);
      for (std::uint32_t i = 0; i < m; ++i) {
        implied[i] += want[i].threshold / m;
        implied[want[i].alias] += (1.0 - want[i].threshold) / m;
      }
      EXPECT_EQ(sampler.alias_probabilities(), implied) << "m " << m << " shape " << shape;
      for (std::uint32_t j = 0; j < 64 * m; ++j) {
        const double u = (j + 0.5) / (64.0 * m);
        const auto i = static_cast<std::uint32_t>(u * m);
        const std::uint32_t expected =
            u * m - static_cast<double>(i) < want[i].threshold ? i : want[i].alias;
        ASSERT_EQ(sampler.pick(u), expected) << "m " << m << " shape " << shape << " u " << u;
      }
    }
  }
}

}  // namespace
}  // namespace pcbench

namespace pcbench {
namespace {

// Every configuration of the family is unbiased on a signed and a positive integrand: one
// Student t test per cell, Holm-corrected at family-wise 1e-3, fixed seed.
TEST(ResamplingUnbiased, EveryConfigurationOnSignedAndPositiveIntegrands) {
  std::vector<GridRequest> grids;
  const std::map<std::string, std::vector<std::string>> integrand_params = {{"light_dims", {"2"}}};
  grids.push_back({.estimators = {"plain"},
                   .integrands = {"genz-gaussian", "genz-oscillatory"},
                   .params = integrand_params,
                   .where = "plain"});
  grids.push_back(
      {.estimators = {"vc-all", "lvc"},
       .integrands = {"genz-gaussian", "genz-oscillatory"},
       .params = {{"M", {"8"}}, {"K", {"3"}}, {"pool", {"fresh", "shared"}}, {"light_dims", {"2"}}},
       .where = "vc"});
  grids.push_back({.estimators = {"pcbpt"},
                   .integrands = {"genz-gaussian", "genz-oscillatory"},
                   .params = {{"M", {"8"}},
                              {"K", {"3"}},
                              {"pool", {"fresh", "shared"}},
                              {"importance", {"approx", "f", "uniform"}},
                              {"sampler", {"alias", "cdf"}},
                              {"light_dims", {"2"}}},
                   .where = "pcbpt"});
  const BudgetDefaults budget{.samples = 10000, .replicates = 16};
  const std::vector<RunPlan> plans = plan_runs(grids, budget);
  ASSERT_EQ(plans.size(), 2u + 8u + 24u);
  expect_family_consistent(plans, 5, 1e-3);
}

}  // namespace
}  // namespace pcbench

namespace pcbench {
namespace {

// Large pools are processed a part of a batch at a time; the split must not change a number.
TEST(ResamplingPools, SplittingALargeBatchChangesNothing) {
  const auto integrand = make_integrand("genz-oscillatory", {});
  for (const char* pool : {"fresh", "shared"}) {
    const auto estimator = make("pcbpt", {{"M", "8192"}, {"K", "3"}, {"pool", pool}});
    std::vector<double> whole(256), part(100);
    Counters counters;
    EstimatorScratch scratch;
    auto workspace = integrand->make_workspace();
    // 256 samples × 8192 candidates exceed one part (2^20 pairs); 100 samples do not.
    estimator->estimate_batch(
        {.key = 5, .first_sample = 512, .sample_count = 256, .counters = &counters}, *workspace,
        scratch, whole);
    estimator->estimate_batch(
        {.key = 5, .first_sample = 512, .sample_count = 100, .counters = &counters}, *workspace,
        scratch, part);
    for (std::size_t i = 0; i < part.size(); ++i) EXPECT_EQ(whole[i], part[i]) << pool << " " << i;
  }
}

}  // namespace
}  // namespace pcbench

namespace pcbench {
namespace {

// The sampler parameter is honoured: alias and CDF draw differently from the same numbers.
TEST(ResamplingSampler, AliasAndCdfAreBothUsed) {
  const auto integrand = make_integrand("genz-oscillatory", {});
  std::vector<std::vector<double>> estimates;
  for (const char* sampler : {"alias", "cdf"}) {
    const auto estimator = make("pcbpt", {{"M", "32"}, {"K", "2"}, {"sampler", sampler}});
    estimates.push_back(run_batch(*estimator, *integrand, 0, 64).estimates);
  }
  EXPECT_NE(estimates[0], estimates[1]);
}

// An infinite importance leaves no valid P: the sample is reported non-finite (never drawn from
// a broken table, which would hide it and bias the estimate).
TEST(ResamplingNonfinite, InfiniteImportanceMakesTheRunInvalid) {
  for (const char* importance : {"approx", "f"}) {
    GridRequest grid{
        .estimators = {"pcbpt"},
        .integrands = {"expr"},
        .params = {{"f", {"x0 < 0.001 ? 1/0 : 1"}}, {"exact", {"1"}}, {"importance", {importance}}},
        .samples = 4096,
        .replicates = 2,
        .where = "test"};
    const RunResult result = execute_run(plan_runs({grid}, {})[0], {});
    EXPECT_EQ(result.status, RunStatus::kInvalid) << importance;
  }
}

}  // namespace
}  // namespace pcbench

namespace pcbench {
namespace {

// The inverse CDF (counting for small tables, binary search for large ones) is the first running
// sum above u × total, and never an entry of probability zero.
TEST(ResamplingSampler, IndexAtIsTheFirstRunningSumAboveTheTarget) {
  for (const std::size_t m : {1, 3, 5, 16, 64, 65, 1000}) {  // each lane count and the tail
    std::vector<double> pmf(m);
    RandomStream init({.key = static_cast<std::uint64_t>(m)});
    for (std::size_t j = 0; j < m; ++j) pmf[j] = j % 3 == 1 ? 0.0 : init.uniform();
    std::vector<double> cdf(m);
    double running = 0.0;
    for (std::size_t j = 0; j < m; ++j) cdf[j] = running += pmf[j];
    DiscreteSampler sampler;
    sampler.build(pmf, DiscreteSamplerKind::kCdf);
    RandomStream rng({.key = 99});
    for (int i = 0; i < 20000; ++i) {
      const double u = rng.uniform();
      const auto expected = static_cast<std::uint32_t>(
          std::upper_bound(cdf.begin(), cdf.end(), u * cdf.back()) - cdf.begin());
      const std::uint32_t index = sampler.index_at(u);
      ASSERT_EQ(index, expected) << "m = " << m << ", u = " << u;
      ASSERT_GT(pmf[index], 0.0);
    }
  }
}

}  // namespace
}  // namespace pcbench
