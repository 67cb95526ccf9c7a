#include "estimators/draw_scheme.h"

#include <algorithm>
#include <cassert>

namespace pcbench {
namespace {

// Running sums of `pmf` divided by their total: index j covers [cdf[j-1], cdf[j]) of [0, 1),
// the same map as DiscreteSampler::index_at.
std::vector<double> normalised_cdf(std::span<const double> pmf) {
  std::vector<double> cdf(pmf.size());
  double running = 0.0;
  for (std::size_t j = 0; j < pmf.size(); ++j) cdf[j] = running += pmf[j];
  for (double& c : cdf) c /= running;
  return cdf;
}

std::uint32_t inverse_cdf(const std::vector<double>& cdf, double u) {
  const auto it = std::upper_bound(cdf.begin(), cdf.end(), u);
  if (it != cdf.end()) return static_cast<std::uint32_t>(it - cdf.begin());
  // u at the very top (rounding): the last index that can be drawn.
  std::size_t j = cdf.size() - 1;
  while (j > 0 && cdf[j] == cdf[j - 1]) --j;
  return static_cast<std::uint32_t>(j);
}

// Depth-first over K positions; `choices(k, draws so far)` lists (index, probability) for the
// next draw given the earlier ones.
using Choices = std::function<std::vector<std::pair<std::uint32_t, double>>(
    std::uint32_t, std::span<const std::uint32_t>)>;

void enumerate_sequences(std::uint32_t K, const Choices& choices, const DrawVisitor& visit,
                         std::vector<std::uint32_t>& draws, double probability) {
  const auto k = static_cast<std::uint32_t>(draws.size());
  if (k == K) {
    visit(probability, draws);
    return;
  }
  bool any = false;
  for (const auto& [j, p] : choices(k, draws)) {
    if (p <= 0.0) continue;
    any = true;
    draws.push_back(j);
    enumerate_sequences(K, choices, visit, draws, probability * p);
    draws.pop_back();
  }
  // Nothing left to draw (without replacement from fewer than K candidates): the sequence ends.
  if (!any) visit(probability, draws);
}

void enumerate_systematic(std::span<const double> pmf, std::uint32_t K, const DrawVisitor& visit) {
  // The draws are a step function of the single uniform u0 in [0, 1): they change only where
  // some (k + u0) / K crosses a CDF boundary. Between breakpoints every u0 gives the same draws.
  const std::vector<double> cdf = normalised_cdf(pmf);
  std::vector<double> breaks = {0.0, 1.0};
  for (double c : cdf) {
    for (std::uint32_t k = 0; k < K; ++k) {
      const double b = c * K - k;
      if (b > 0.0 && b < 1.0) breaks.push_back(b);
    }
  }
  std::sort(breaks.begin(), breaks.end());
  std::vector<std::uint32_t> draws(K);
  for (std::size_t b = 0; b + 1 < breaks.size(); ++b) {
    const double width = breaks[b + 1] - breaks[b];
    if (width <= 0.0) continue;
    const double u0 = 0.5 * (breaks[b] + breaks[b + 1]);
    for (std::uint32_t k = 0; k < K; ++k) draws[k] = inverse_cdf(cdf, (k + u0) / K);
    visit(width, draws);
  }
}

}  // namespace

const char* to_string(DrawScheme scheme) {
  switch (scheme) {
    case DrawScheme::kEvery:
      return "every";
    case DrawScheme::kIndependent:
      return "independent";
    case DrawScheme::kStratified:
      return "stratified";
    case DrawScheme::kSystematic:
      return "systematic";
    case DrawScheme::kWithoutReplacement:
      return "without-replacement";
  }
  return "every";
}

void draw_indices(DrawScheme scheme, std::span<const double> pmf, std::uint32_t K,
                  DiscreteSamplerKind kind, DiscreteSampler& sampler, RandomStream& rng,
                  std::vector<std::uint32_t>& out) {
  out.clear();
  const auto m = static_cast<std::uint32_t>(pmf.size());
  switch (scheme) {
    case DrawScheme::kEvery:
      for (std::uint32_t j = 0; j < m; ++j) out.push_back(j);
      return;
    case DrawScheme::kIndependent:
      sampler.build(pmf, kind);
      for (std::uint32_t k = 0; k < K; ++k) out.push_back(sampler.draw(rng));
      return;
    case DrawScheme::kStratified:
      sampler.build(pmf, DiscreteSamplerKind::kCdf);
      for (std::uint32_t k = 0; k < K; ++k)
        out.push_back(sampler.index_at((k + rng.uniform()) / K));
      return;
    case DrawScheme::kSystematic: {
      sampler.build(pmf, DiscreteSamplerKind::kCdf);
      const double u0 = rng.uniform();
      for (std::uint32_t k = 0; k < K; ++k) out.push_back(sampler.index_at((k + u0) / K));
      return;
    }
    case DrawScheme::kWithoutReplacement: {
      // Successive sampling: each draw from what is left, in proportion to P. O(M K), and only
      // the negative control uses it.
      std::vector<double> left(pmf.begin(), pmf.end());
      for (std::uint32_t k = 0; k < K; ++k) {
        double total = 0.0;
        for (double p : left) total += p;
        if (!(total > 0.0)) return;  // fewer than K candidates can be drawn: fewer draws
        const double target = rng.uniform() * total;
        double running = 0.0;
        std::uint32_t chosen = m;
        for (std::uint32_t j = 0; j < m; ++j) {
          if (left[j] <= 0.0) continue;
          chosen = j;  // the last one left, should rounding carry the target past the total
          running += left[j];
          if (target < running) break;
        }
        assert(chosen < m);
        out.push_back(chosen);
        left[chosen] = 0.0;
      }
      return;
    }
  }
}

void enumerate_draws(DrawScheme scheme, std::span<const double> pmf, std::uint32_t K,
                     const DrawVisitor& visit) {
  const auto m = static_cast<std::uint32_t>(pmf.size());
  std::vector<std::uint32_t> draws;
  double total = 0.0;
  for (double p : pmf) total += p;
  switch (scheme) {
    case DrawScheme::kEvery:
      for (std::uint32_t j = 0; j < m; ++j) draws.push_back(j);
      visit(1.0, draws);
      return;
    case DrawScheme::kIndependent:
      enumerate_sequences(
          K,
          [&](std::uint32_t, std::span<const std::uint32_t>) {
            std::vector<std::pair<std::uint32_t, double>> next;
            for (std::uint32_t j = 0; j < m; ++j) next.emplace_back(j, pmf[j] / total);
            return next;
          },
          visit, draws, 1.0);
      return;
    case DrawScheme::kStratified: {
      // Stratum k draws j with probability K |[k/K, (k+1)/K) ∩ [cdf[j-1], cdf[j])|.
      const std::vector<double> cdf = normalised_cdf(pmf);
      enumerate_sequences(
          K,
          [&](std::uint32_t k, std::span<const std::uint32_t>) {
            std::vector<std::pair<std::uint32_t, double>> next;
            const double lo = static_cast<double>(k) / K;
            const double hi = static_cast<double>(k + 1) / K;
            for (std::uint32_t j = 0; j < m; ++j) {
              const double a = std::max(lo, j == 0 ? 0.0 : cdf[j - 1]);
              const double b = std::min(hi, cdf[j]);
              next.emplace_back(j, b > a ? (b - a) * K : 0.0);
            }
            return next;
          },
          visit, draws, 1.0);
      return;
    }
    case DrawScheme::kSystematic:
      enumerate_systematic(pmf, K, visit);
      return;
    case DrawScheme::kWithoutReplacement:
      enumerate_sequences(
          K,
          [&](std::uint32_t, std::span<const std::uint32_t> earlier) {
            double left = total;
            for (std::uint32_t j : earlier) left -= pmf[j];
            std::vector<std::pair<std::uint32_t, double>> next;
            for (std::uint32_t j = 0; j < m; ++j) {
              const bool taken = std::find(earlier.begin(), earlier.end(), j) != earlier.end();
              next.emplace_back(j, taken ? 0.0 : pmf[j] / left);
            }
            return next;
          },
          visit, draws, 1.0);
      return;
  }
}

}  // namespace pcbench
