// The reservoir estimators (ris, restir): the streaming reservoir against its enumeration, ris
// equal in distribution to pcbpt without mixing, the reuse weights' partition of unity, and the
// honest forms unbiased.
//
// Error budgets: the reservoir's chi-square test at 1e-6 (fixed seed); the unbiasedness runs one
// Holm family at 1e-3 (fixed seed). The enumerations are exact up to rounding (1e-12).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "estimators/resampling_step.h"
#include "estimators/reservoir_estimator.h"
#include "harness/plan/plan.h"
#include "harness/run/runner.h"
#include "harness/verify/statistics.h"
#include "test_support.h"

namespace pcbench {
namespace {

const std::vector<double> kWeights = {0.4, 0.0, 2.5, 1e-3, 0.9, 0.0, 3.1};

// The reservoir keeps j with probability w_j / Σ w, by its own acceptances.
TEST(ReservoirSampling, EnumeratedProbabilitiesAreTheNormalisedWeights) {
  std::vector<double> p;
  const Reservoir reservoir = reservoir_probabilities(kWeights, p);
  double total = 0.0;
  for (double w : kWeights) total += w;
  EXPECT_DOUBLE_EQ(reservoir.weight_sum(), total);
  for (std::size_t j = 0; j < kWeights.size(); ++j) EXPECT_NEAR(p[j], kWeights[j] / total, 1e-15);
  const std::vector<double> zeros(3, 0.0);
  reservoir_probabilities(zeros, p);
  for (double q : p) EXPECT_EQ(q, 0.0);
}

// 200000 sampled reservoirs follow the enumeration (chi-square, budget 1e-6, fixed seed), and
// zero weights are never kept.
TEST(ReservoirSampling, SampledChoicesFollowTheEnumeration) {
  constexpr int kDraws = 200000;
  std::vector<double> p;
  reservoir_probabilities(kWeights, p);
  std::vector<double> seen(kWeights.size(), 0.0);
  for (int i = 0; i < kDraws; ++i) {
    RandomStream rng({.key = 31, .sample = static_cast<std::uint32_t>(i)});
    Reservoir reservoir;
    for (std::uint32_t j = 0; j < kWeights.size(); ++j) reservoir.offer(j, kWeights[j], rng);
    ASSERT_FALSE(reservoir.empty());
    seen[reservoir.kept()] += 1.0;
  }
  EXPECT_EQ(seen[1] + seen[5], 0.0);
  std::vector<double> observed;
  std::vector<double> expected;
  for (std::size_t j = 0; j < p.size(); ++j) {
    if (p[j] == 0.0) continue;
    observed.push_back(seen[j]);
    expected.push_back(p[j]);
  }
  EXPECT_GT(chi_square_p_value(observed, expected), 1e-6);
}

// A batch's inverse transform picks the candidate whose interval of the running sums holds u
// times their total, never one of weight 0 (leading, inner or trailing), up to the last u below
// 1; over a fine grid of u each candidate's share is its normalised weight to within the grid's
// spacing.
TEST(ReservoirSampling, InverseTransformPicksTheIntervalOfU) {
  const std::vector<double> weights = {0.0, 0.4, 0.0, 2.5, 1e-3, 0.9, 0.0, 3.1, 0.0};
  std::vector<double> running;
  double total = 0.0;
  for (const double w : weights) running.push_back(total += w);
  constexpr int kGrid = 1 << 16;
  std::vector<double> share(weights.size(), 0.0);
  std::vector<double> us;
  for (int k = 0; k < kGrid; ++k) us.push_back((k + 0.5) / kGrid);
  us.insert(us.end(), {0.0, std::nextafter(1.0, 0.0)});
  for (const double u : us) {
    const std::uint32_t j = Reservoir::inverse_transform(running, u);
    ASSERT_LT(j, weights.size());
    ASSERT_GT(weights[j], 0.0) << "u = " << u;
    const double target = u * total;
    EXPECT_TRUE((j == 0 || running[j - 1] <= target) && (target < running[j] || u * total >= total))
        << "u = " << u << ", j = " << j;
    if (u != us[kGrid] && u != us[kGrid + 1]) share[j] += 1.0 / kGrid;
  }
  for (std::size_t j = 0; j < weights.size(); ++j) {
    EXPECT_NEAR(share[j], weights[j] / total, 2.0 / kGrid) << j;
  }
}

// offer_batch keeps each candidate with its share of every weight offered so far: after one
// candidate offered alone, the weights in one batch and in two (the second kept against the
// first as one candidate of its total), 200000 sampled reservoirs each against w_j / Σ w
// (chi-square, budget 1e-6 each, fixed seed); zero weights never kept, and the sum is Σ w.
TEST(ReservoirSampling, OfferBatchFollowsTheNormalisedWeights) {
  constexpr int kDraws = 200000;
  constexpr double kFirst = 2.0;
  double total = kFirst;
  for (const double w : kWeights) total += w;
  for (const std::size_t split : {kWeights.size(), std::size_t{3}}) {
    std::vector<double> seen(kWeights.size() + 1, 0.0);
    for (int i = 0; i < kDraws; ++i) {
      RandomStream rng({.key = 33, .sample = static_cast<std::uint32_t>(i)});
      Reservoir reservoir;
      reservoir.offer(0, kFirst, rng);
      reservoir.offer_batch(1, std::span(kWeights).first(split), rng);
      if (split < kWeights.size()) {
        reservoir.offer_batch(1 + static_cast<std::uint32_t>(split),
                              std::span(kWeights).subspan(split), rng);
      }
      ASSERT_FALSE(reservoir.empty());
      if (i == 0) {
        EXPECT_NEAR(reservoir.weight_sum(), total, 1e-14 * total);
      }
      seen[reservoir.kept()] += 1.0;
    }
    std::vector<double> observed = {seen[0]}, expected = {kFirst / total};
    for (std::size_t j = 0; j < kWeights.size(); ++j) {
      if (kWeights[j] == 0.0) {
        EXPECT_EQ(seen[1 + j], 0.0) << j;
        continue;
      }
      observed.push_back(seen[1 + j]);
      expected.push_back(kWeights[j] / total);
    }
    EXPECT_GT(chi_square_p_value(observed, expected), 1e-6) << "split " << split;
  }
}

// Sequence of pool indices -> (probability, Σ coefficients of its terms) of one enumeration.
using Distribution = std::map<std::vector<std::uint32_t>, std::pair<double, double>>;

void add(Distribution& d, double probability, std::span<const Term> terms) {
  std::vector<std::uint32_t> key;
  double coefficients = 0.0;
  for (const Term& t : terms) {
    key.push_back(t.index);
    coefficients += t.coefficient;
  }
  auto& [p, c] = d[key];
  p += probability;
  c = coefficients;
}

void expect_same(const Distribution& a, const Distribution& b, const std::string& where) {
  ASSERT_EQ(a.size(), b.size()) << where;
  for (const auto& [key, pc] : a) {
    ASSERT_TRUE(b.count(key)) << where;
    EXPECT_NEAR(pc.first, b.at(key).first, 1e-12) << where;
    EXPECT_NEAR(pc.second, b.at(key).second, 1e-12 * std::fabs(pc.second)) << where;
  }
}

// ris is pcbpt with uniform_mix = 0, K draws with replacement and importance w = p̂/q: for the
// same streams (the same camera paths and pools), every camera sample's draws have the same
// distribution and the same weights, on uniform (blocker, genz-oscillatory) and non-uniform
// (linear-emitter, genz-continuous) light densities, for every target and K = 1 and 2. (Where
// every w is 0, pcbpt falls back to uniform P and ris keeps nothing; f is then 0 on the pool.)
TEST(ReservoirRis, EqualInDistributionToPcbptWithoutMixing) {
  for (const char* integrand :
       {"blocker", "genz-oscillatory", "linear-emitter", "genz-continuous"}) {
    for (const char* target : {"approx", "f", "uniform"}) {
      for (const char* k : {"1", "2"}) {
        const RunPlan plan =
            plan_single("ris", integrand, {{"M", {"5"}}, {"K", {k}}, {"target", {target}}}, 1, 2);
        const auto& ris = dynamic_cast<const ReservoirEstimator&>(*plan.made_estimator);
        const std::unique_ptr<PathWorkspace> paths = plan.made_integrand->make_workspace();
        EstimatorScratch scratch;
        const BatchContext ctx{.key = 99, .sample_count = 16};
        const ReservoirBatch batch = ris.prepare(ctx, *paths, scratch, true);
        const ResamplingStep pcbpt({.M = 5,
                                    .K = ris.config().K,
                                    .selection = Selection::kImportance,
                                    .scheme = DrawScheme::kIndependent,
                                    .uniform_mix = 0.0});
        std::array<double, 5> w{};
        for (std::uint32_t i = 0; i < ctx.sample_count; ++i) {
          for (std::uint32_t j = 0; j < 5; ++j) {
            w[j] = batch.target[i * 5 + j] / batch.light_pdf[batch.pools.pool_start(i) + j];
          }
          if (std::all_of(w.begin(), w.end(), [](double v) { return v == 0.0; })) {
            // The reservoir keeps nothing and pcbpt draws uniformly from a pool where f = 0:
            // both estimates are 0.
            for (std::uint32_t j = 0; j < 5; ++j) EXPECT_EQ(scratch.contributions[i * 5 + j], 0.0);
            continue;
          }
          const PoolView view{
              .importance = w,
              .contributions = std::span<const double>(scratch.contributions).subspan(i * 5, 5)};
          Distribution of_ris;
          Distribution of_pcbpt;
          ris.enumerate(batch, i, [&](double p, std::span<const Term> t) { add(of_ris, p, t); });
          pcbpt.enumerate(view, [&](double p, std::span<const Term> t) { add(of_pcbpt, p, t); });
          expect_same(of_ris, of_pcbpt, std::string(integrand) + " target=" + target + " K=" + k);
        }
      }
    }
  }
}

// At every x where the canonical sample's target is > 0, the honest weights of the sources that
// can produce x (T > 0) sum to 1; the naive ones do not once a neighbour's target is 0.
TEST(ReservoirReuseWeights, HonestFormsArePartitionsOfUnity) {
  const std::vector<std::vector<double>> cases = {
      {1.0, 2.0, 0.5}, {0.3, 0.0, 4.0, 0.0}, {2.0, 0.0}, {1e-300, 1e300, 1.0}, {5.0}};
  for (const auto& targets : cases) {
    for (ReuseWeights form : {ReuseWeights::kBalance, ReuseWeights::kPairwise, ReuseWeights::kCount,
                              ReuseWeights::kUniform}) {
      double covering = 0.0;
      for (std::size_t s = 0; s < targets.size(); ++s) {
        const double m = reuse_mis_weight({.form = form}, targets, s);
        EXPECT_GE(m, 0.0);
        if (targets[s] > 0.0) covering += m;
      }
      const bool some_zero = std::count(targets.begin(), targets.end(), 0.0) > 0;
      if (form == ReuseWeights::kUniform && some_zero) {
        EXPECT_LT(covering, 1.0 - 1e-3);
      } else {
        EXPECT_NEAR(covering, 1.0, 1e-12) << static_cast<int>(form);
      }
    }
  }
  // The naive form at naive_share 0 is the honest 1/Z.
  const std::vector<double> targets = {0.3, 0.0, 4.0};
  EXPECT_DOUBLE_EQ(
      reuse_mis_weight({.form = ReuseWeights::kUniform, .naive_share = 0.0}, targets, 0), 0.5);
}

// Every honest form is unbiased on a signed integrand, a non-uniform density and visibility: one
// Student t test per run against the exact value, Holm family at 1e-3, fixed seed.
TEST(ReservoirUnbiased, HonestFormsOnSignedNonUniformAndOccludedIntegrands) {
  const std::vector<std::string> integrands = {"genz-oscillatory", "linear-emitter", "blocker"};
  const std::vector<GridRequest> grids = {
      {.estimators = {"ris"},
       .integrands = integrands,
       .params = {{"M", {"8"}},
                  {"K", {"1", "3"}},
                  {"target", {"approx", "f", "uniform"}},
                  {"pool", {"fresh", "shared"}}},
       .where = "ris"},
      {.estimators = {"restir"},
       .integrands = integrands,
       .params = {{"M", {"8"}},
                  {"N", {"3"}},
                  {"rounds", {"1", "2"}},
                  {"target", {"approx", "f"}},
                  {"weights", {"balance", "pairwise", "count"}}},
       .where = "restir"}};
  const std::vector<RunPlan> plans = plan_runs(grids, {.samples = 20000, .replicates = 16});
  ASSERT_EQ(plans.size(), 36u + 36u);
  expect_family_consistent(plans, 7, 1e-3);
}

}  // namespace
}  // namespace pcbench
