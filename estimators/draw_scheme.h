// How the K connections of a camera sample are drawn from P(j | y, X), and every way they can
// come out (for the exact check of the resampling step).
//
// Unbiasedness needs E[number of times j is drawn | y, X] = K P_j (DESIGN.md). Independent draws
// with replacement give it, and so do stratified and systematic draws through the inverse CDF,
// although their single draws are not distributed as P: stratum k maps u in [k/K, (k+1)/K) to
// an index, and the strata together cover [0, 1) once. Draws *without* replacement do not
// (their inclusion probabilities are not K P_j unless P is uniform); they exist for a negative
// control.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "base/discrete_sampler.h"
#include "base/rng.h"

namespace pcbench {

enum class DrawScheme {
  kEvery,               // every index once (K = M), as vertex connection does
  kIndependent,         // K independent draws with replacement
  kStratified,          // one draw per stratum [k/K, (k+1)/K) of the inverse CDF
  kSystematic,          // one uniform u, draws at (k + u) / K of the inverse CDF
  kWithoutReplacement,  // successive draws, each from P restricted to what is left
};

const char* to_string(DrawScheme scheme);

// Draws into `out` (cleared first): M indices for kEvery, else K. `pmf` sums to 1 up to
// rounding and has an entry > 0; kWithoutReplacement stops early when fewer than K entries
// are > 0.
// `kind` chooses the sampler of independent draws; the other schemes use the inverse CDF by
// definition.
void draw_indices(DrawScheme scheme, std::span<const double> pmf, std::uint32_t K,
                  DiscreteSamplerKind kind, DiscreteSampler& sampler, RandomStream& rng,
                  std::vector<std::uint32_t>& out);

// Calls visit(probability, draws) once for every sequence of draws the scheme can make from
// `pmf` with a probability > 0 (the probabilities sum to 1). There are up to M^K sequences:
// meant for small pools (the exact check uses M <= 6, K <= 3).
using DrawVisitor = std::function<void(double, std::span<const std::uint32_t>)>;
void enumerate_draws(DrawScheme scheme, std::span<const double> pmf, std::uint32_t K,
                     const DrawVisitor& visit);

}  // namespace pcbench
