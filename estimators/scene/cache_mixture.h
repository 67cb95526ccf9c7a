// The draw of probabilistic connections at one camera vertex (pcbpt.cpp): the mixture of its
// nearest cache points' P and a uniform share u over the N_v candidates,
//     p(i) = u / N_v + (1 - u) / |C| Σ_{c∈C} P_c(i),
// a cache point without a P (it sees nothing) counting as uniform. draw() follows the mixture's
// branches (uniform with probability u, else one cache point uniformly, then its P), and pmf()
// is the exact probability of that draw, which the connection's weight 1 / (K M p) uses;
// tests/cache_mixture_test.cpp enumerates the branches against it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "base/discrete_sampler.h"
#include "base/rng.h"

namespace pcbench::scene {

// One cache point's distribution over the candidates (empty pmf: none, counts as uniform).
struct CacheDistribution {
  std::vector<double> pmf;
  DiscreteSampler sampler;
};

class CacheMixture {
 public:
  // `caches` must outlive the mixture; `nearest` indexes them (empty: the draw is uniform).
  CacheMixture(std::span<const CacheDistribution> caches, std::span<const std::uint32_t> nearest,
               std::uint32_t candidates, double uniform_mix)
      : caches_(caches),
        nearest_(nearest),
        n_(candidates),
        u_(nearest.empty() ? 1.0 : uniform_mix),
        share_(nearest.empty() ? 0.0 : (1.0 - u_) / static_cast<double>(nearest.size())) {}

  double uniform_share() const { return u_; }
  std::span<const std::uint32_t> nearest() const { return nearest_; }

  // The drawn candidate, or none when `empty_draws_nothing` and the chosen cache point has no P
  // (the negative control's mistake).
  std::optional<std::uint32_t> draw(RandomStream& rng, bool empty_draws_nothing = false) const {
    std::optional<std::uint32_t> drawn;
    draw_many(rng, empty_draws_nothing, std::span(&drawn, 1));
    return drawn;
  }

  // The most draws draw_many() makes at once.
  static constexpr std::size_t kMaxMany = 16;

  // drawn.size() (at most kMaxMany) calls of draw(), the same numbers in the same order: every
  // draw's random numbers first, then the samplers' table lookups, which miss the cache (the
  // tables are caches × N_v entries) and so overlap rather than wait one after the other.
  void draw_many(RandomStream& rng, bool empty_draws_nothing,
                 std::span<std::optional<std::uint32_t>> drawn) const {
    const DiscreteSampler* sampler[kMaxMany];
    DiscreteSampler::Numbers numbers[kMaxMany];
    for (std::size_t d = 0; d < drawn.size(); ++d) {
      sampler[d] = nullptr;
      if (rng.uniform() < u_) {
        drawn[d] = rng.uniform_index(n_);
        continue;
      }
      const CacheDistribution& c =
          caches_[nearest_[rng.uniform_index(static_cast<std::uint32_t>(nearest_.size()))]];
      if (c.pmf.empty()) {
        drawn[d] = empty_draws_nothing ? std::nullopt
                                       : std::optional<std::uint32_t>(rng.uniform_index(n_));
        continue;
      }
      sampler[d] = &c.sampler;
      numbers[d] = c.sampler.numbers(rng);
      c.sampler.prefetch(numbers[d]);
    }
    for (std::size_t d = 0; d < drawn.size(); ++d) {
      if (sampler[d] != nullptr) drawn[d] = sampler[d]->resolve(numbers[d]);
      if (drawn[d]) prefetch_pmf(*drawn[d]);
    }
  }

  // Starts the loads pmf(index) makes (an entry of each nearest cache point's P, tables that
  // miss the cache), so that a batch's overlap.
  void prefetch_pmf(std::uint32_t index) const {
    for (std::uint32_t c : nearest_) {
      if (!caches_[c].pmf.empty()) __builtin_prefetch(&caches_[c].pmf[index]);
    }
  }

  double pmf(std::uint32_t index) const {
    const double uniform = 1.0 / n_;
    double p = u_ * uniform;
    for (std::uint32_t c : nearest_) {
      p += share_ * (caches_[c].pmf.empty() ? uniform : caches_[c].pmf[index]);
    }
    return p;
  }

 private:
  std::span<const CacheDistribution> caches_;
  std::span<const std::uint32_t> nearest_;
  std::uint32_t n_;
  double u_, share_;
};

}  // namespace pcbench::scene
