// pcbpt's draw at one camera vertex (estimators/scene/cache_mixture.h): the mixture of its nearest
// cache points' P and the uniform share. The weight 1 / (K M p) is unbiased only if p is the
// probability with which draw() picks each candidate and is positive wherever f is: checked by
// drawing (a binomial test per candidate) and by enumerating the estimate's expectation over
// the candidates exactly, which must equal connecting to every one of them.
#include "estimators/scene/cache_mixture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "harness/run/diagnostics.h"

namespace pcbench::scene {
namespace {

constexpr std::uint32_t kCandidates = 7;

CacheDistribution distribution(std::vector<double> weights) {
  CacheDistribution d;
  double total = 0.0;
  for (double w : weights) total += w;
  for (double& w : weights) w /= total;
  d.pmf = std::move(weights);
  d.sampler.build(d.pmf, DiscreteSamplerKind::kAlias);
  return d;
}

// Four cache points: peaked, zero on some candidates, seeing nothing (no P), spread.
std::vector<CacheDistribution> caches() {
  std::vector<CacheDistribution> c;
  c.push_back(distribution({50, 1, 1, 1, 1, 1, 1}));
  c.push_back(distribution({0, 3, 0, 2, 0, 1, 0}));
  c.push_back(CacheDistribution{});
  c.push_back(distribution({1, 2, 3, 4, 5, 6, 7}));
  return c;
}

// E[Σ_k 1/(K M p(ξ_k)) f(ξ_k)] enumerated over one draw (times K) against Σ_i f_i / M.
double enumerated_expectation(const CacheMixture& mixture, const std::vector<double>& f, double k,
                              double m) {
  double expectation = 0.0;
  for (std::uint32_t i = 0; i < kCandidates; ++i) {
    const double p = mixture.pmf(i);
    if (p > 0.0) expectation += k * p * (1.0 / (k * m * p)) * f[i];
  }
  return expectation;
}

TEST(CacheMixture, PmfIsTheDrawsProbability) {
  const std::vector<CacheDistribution> c = caches();
  const std::vector<std::uint32_t> nearest = {0, 1, 2};
  const CacheMixture mixture(c, nearest, kCandidates, 0.25);
  double total = 0.0;
  for (std::uint32_t i = 0; i < kCandidates; ++i) total += mixture.pmf(i);
  EXPECT_NEAR(total, 1.0, 1e-12);
  // 200000 draws; a binomial test per candidate, Bonferroni over 7 at a budget of 1e-4 (fixed
  // seed: the outcome is deterministic, the budget says how unlikely a false failure was).
  constexpr std::uint64_t kDraws = 200000;
  std::vector<std::uint64_t> counts(kCandidates, 0);
  RandomStream rng({.key = 16, .purpose = StreamPurpose::kResampling});
  for (std::uint64_t d = 0; d < kDraws; ++d) ++counts[*mixture.draw(rng)];
  for (std::uint32_t i = 0; i < kCandidates; ++i) {
    const double p = binomial_test_p_value(counts[i], kDraws, mixture.pmf(i));
    EXPECT_GT(p * kCandidates, 1e-4)
        << "candidate " << i << ": " << counts[i] << " draws, pmf " << mixture.pmf(i);
  }
}

TEST(CacheMixture, EnumeratedExpectationIsConnectingToEveryCandidate) {
  const std::vector<CacheDistribution> c = caches();
  const std::vector<double> f = {0.3, 0.0, 2.0, 1.0, 0.5, 0.0, 4.0};
  const double m = 3.0, k = 3.0;
  double exact = 0.0;
  for (double fi : f) exact += fi / m;
  for (const std::vector<std::uint32_t>& nearest :
       {std::vector<std::uint32_t>{0, 1, 2}, {1}, {2}, {1, 3}, {}}) {
    const CacheMixture mixture(c, nearest, kCandidates, 0.25);
    EXPECT_NEAR(enumerated_expectation(mixture, f, k, m), exact, 1e-12 * exact)
        << nearest.size() << " nearest";
  }
}

// The check can fail: without the uniform share, a cache point that is zero where f is not
// (cache 1 on candidates 0, 2, 4, 6) loses their contribution (the negative control's bias).
TEST(CacheMixture, WithoutTheUniformShareTheEnumerationShowsTheBias) {
  const std::vector<CacheDistribution> c = caches();
  const std::vector<double> f = {0.3, 0.0, 2.0, 1.0, 0.5, 0.0, 4.0};
  const std::vector<std::uint32_t> nearest = {1};
  const CacheMixture mixture(c, nearest, kCandidates, 0.0);
  double exact = 0.0;
  for (double fi : f) exact += fi;
  EXPECT_NEAR(enumerated_expectation(mixture, f, 1.0, 1.0), 1.0, 1e-12);  // only candidate 3
  EXPECT_LT(enumerated_expectation(mixture, f, 1.0, 1.0), exact);
  // And a cache point that sees nothing draws nothing when told to (the control's mistake).
  const std::vector<std::uint32_t> blind = {2};
  const CacheMixture control(c, blind, kCandidates, 0.0);
  RandomStream rng({.key = 17});
  EXPECT_FALSE(control.draw(rng, true).has_value());
}

// pcbpt draws a batch at once (draw_many: every draw's random numbers, then the table lookups);
// the batch must be the draws that one draw() after another gives from the same stream, with the
// streams left at the same place, whichever branches (uniform, a P, a cache point without one,
// the control's nothing) the draws take.
TEST(CacheMixture, DrawManyIsDrawAfterDraw) {
  const std::vector<CacheDistribution> c = caches();
  for (const bool nothing : {false, true}) {
    for (const std::vector<std::uint32_t>& nearest :
         {std::vector<std::uint32_t>{0, 1, 2}, {2, 3}, {}}) {
      const CacheMixture mixture(c, nearest, kCandidates, 0.25);
      RandomStream one({.key = 18}), many({.key = 18});
      for (std::size_t size = 1; size <= CacheMixture::kMaxMany; ++size) {
        std::optional<std::uint32_t> batch[CacheMixture::kMaxMany];
        mixture.draw_many(many, nothing, std::span(batch, size));
        for (std::size_t d = 0; d < size; ++d) {
          EXPECT_EQ(batch[d], mixture.draw(one, nothing)) << "draw " << d << " of " << size;
        }
      }
      EXPECT_EQ(one.uniform(), many.uniform());
    }
  }
}

}  // namespace
}  // namespace pcbench::scene
