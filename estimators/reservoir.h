// A weighted reservoir (Chao 1982), as ReSTIR keeps one: candidates stream through once and the
// reservoir holds one of them and the running sum of their weights, O(1) memory. Candidate j of
// weight w_j replaces the kept one with probability a_j = w_j / Σ_{l<=j} w_l, so the one kept at
// the end is j with probability
//     a_j Π_{l>j} (1 - a_l) = w_j / Σ_l w_l,
// which is what resampled importance sampling needs: a draw in proportion to w, and Σ w for the
// contribution weight. The sampled reservoir (`offer`) and the exact enumeration
// (`reservoir_probabilities`) both take a_j from `acceptance`, so the enumeration describes the
// procedure as run, not the formula it is meant to follow.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "base/rng.h"

namespace pcbench {

class Reservoir {
 public:
  static constexpr std::uint32_t kEmpty = std::numeric_limits<std::uint32_t>::max();

  // Streams a candidate of weight w >= 0 into the sum; returns the probability a that it
  // replaces the kept one (0 for w = 0, 1 for the first candidate of positive weight).
  double acceptance(double w) {
    sum_ += w;
    return w > 0.0 ? w / sum_ : 0.0;
  }
  // Streams candidate j, kept if u < a. A uniform is read only when 0 < a < 1, so a candidate
  // that cannot change the outcome consumes no random number.
  void offer(std::uint32_t j, double w, RandomStream& rng) {
    const double a = acceptance(w);
    if (a >= 1.0 || (a > 0.0 && rng.uniform() < a)) kept_ = j;
  }
  // offer() for candidates first, first + 1, … of `weights`, in order: the same choices from
  // the same numbers, the uniforms the acceptances need (one for each 0 < a < 1) read from `rng`
  // kBatch candidates at a time (RandomStream::uniforms), and no branch on a candidate (each
  // u < a is a coin flip a branch would mispredict half the time).
  static constexpr std::size_t kBatch = 64;
  void offer_all(std::uint32_t first, std::span<const double> weights, RandomStream& rng) {
    for (std::size_t start = 0; start < weights.size(); start += kBatch) {
      const std::size_t n = std::min(kBatch, weights.size() - start);
      double accept[kBatch], u[kBatch + 1];
      std::size_t draws = 0;
      for (std::size_t j = 0; j < n; ++j) {
        accept[j] = acceptance(weights[start + j]);
        draws += static_cast<std::size_t>((accept[j] > 0.0) & (accept[j] < 1.0));
      }
      rng.uniforms(std::span(u, draws));
      u[draws] = 1.0;  // read by the candidates after the last draw, and never used
      std::size_t k = 0;
      std::uint32_t kept = kept_;
      for (std::size_t j = 0; j < n; ++j) {
        const double a = accept[j];
        const bool draws_one = (a > 0.0) & (a < 1.0);
        const bool take = (a >= 1.0) | (draws_one & (u[k] < a));
        // A select on the bits: written as a ternary, GCC branched on `take`.
        const std::uint32_t mask = 0u - static_cast<std::uint32_t>(take);
        kept ^= (kept ^ (first + static_cast<std::uint32_t>(start + j))) & mask;
        k += static_cast<std::size_t>(draws_one);
      }
      kept_ = kept;
    }
  }
  void keep(std::uint32_t j) { kept_ = j; }

  std::uint32_t kept() const { return kept_; }
  bool empty() const { return kept_ == kEmpty; }
  double weight_sum() const { return sum_; }

 private:
  std::uint32_t kept_ = kEmpty;
  double sum_ = 0.0;
};

// The probability that a reservoir streamed over `weights` in order keeps each candidate, from
// the acceptances it makes (into `out`, which sums to 1 unless every weight is 0); returns the
// reservoir with its sum and nothing kept.
inline Reservoir reservoir_probabilities(std::span<const double> weights,
                                         std::vector<double>& out) {
  Reservoir reservoir;
  out.assign(weights.size(), 0.0);
  for (std::size_t j = 0; j < weights.size(); ++j) out[j] = reservoir.acceptance(weights[j]);
  double survive = 1.0;  // Π_{l>j} (1 - a_l), from the last candidate back
  for (std::size_t j = weights.size(); j-- > 0;) {
    const double a = out[j];
    out[j] = a * survive;
    survive *= 1.0 - a;
  }
  return reservoir;
}

}  // namespace pcbench
