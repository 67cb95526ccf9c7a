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
  // A batch of candidates first, first + 1, … of `weights` (at most kBatch) at once, with the
  // distribution offer() gives them one by one: candidate j of the batch kept with probability
  // w_j / Σ w over every candidate so far. The batch's own choice is one uniform's inverse
  // transform over its running sums (`inverse_transform`), kept against the candidates of
  // earlier batches as one candidate of the batch's total weight (a second uniform, only when an
  // earlier batch kept one). One candidate at a time drew a uniform per acceptance and waited on
  // a division each (docs/findings/candidates.md).
  static constexpr std::size_t kBatch = 64;
  void offer_batch(std::uint32_t first, std::span<const double> weights, RandomStream& rng) {
    double running[kBatch];
    double batch = 0.0;
    for (std::size_t j = 0; j < weights.size(); ++j) running[j] = batch += weights[j];
    if (!(batch > 0.0)) return;
    const bool earlier = !empty();
    sum_ += batch;
    if (earlier && !(rng.uniform() * sum_ < batch)) return;
    kept_ = first + inverse_transform(std::span(running, weights.size()), rng.uniform());
  }
  // The candidate whose interval [R_{j-1}, R_j) of the running sums R holds u R_last: the first
  // j with R_j > u R_last, found by counting (no branch a coin flip mispredicts), and never one
  // of weight 0 (where rounding puts u R_last at R_last itself: the last of positive weight).
  static std::uint32_t inverse_transform(std::span<const double> running, double u) {
    const double total = running.back(), target = u * total;
    std::uint32_t below = 0, last_positive = 0;
    for (std::size_t j = 0; j < running.size(); ++j) {
      below += running[j] <= target ? 1u : 0u;
      const bool positive = running[j] > (j > 0 ? running[j - 1] : 0.0);
      last_positive = positive ? static_cast<std::uint32_t>(j) : last_positive;
    }
    return std::min(below, last_positive);
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
