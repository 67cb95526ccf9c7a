// Drawing indices from a discrete distribution P over a pool of M entries, as probabilistic
// connections do K times per camera sample.
//
// Two ways, both O(M) to build: Vose's alias method (O(1) per draw; M. D. Vose, "A linear
// algorithm for generating random numbers with a given distribution", IEEE TSE 1991) and the
// inverse CDF by binary search (O(log M) per draw). The benchmarks measure which is faster for
// which M and K: the CDF's build is a single pass and wins unless K approaches M. Either way the
// estimator weights a draw by the P it computed, not by what the table implies, so rounding in the
// table cannot bias the estimate.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "base/rng.h"

namespace pcbench {

enum class DiscreteSamplerKind { kAlias, kCdf };

class DiscreteSampler {
 public:
  // `pmf` must be non-negative with a positive sum (it need not be normalised exactly).
  void build(std::span<const double> pmf, DiscreteSamplerKind kind);
  std::uint32_t draw(RandomStream& rng) const;
  // The inverse CDF at u in [0, 1): the first index whose running sum exceeds u × total. Only for
  // a table built as kCdf (stratified and systematic draws need this map, not just any draw).
  std::uint32_t index_at(double u) const;

 private:
  static constexpr std::size_t kLinearSearchMax = 64;  // inverse CDF by counting up to here

  DiscreteSamplerKind kind_ = DiscreteSamplerKind::kAlias;
  std::vector<double> threshold_;     // alias: keep i with probability threshold_[i]
  std::vector<std::uint32_t> alias_;  // alias: else take alias_[i]
  std::vector<std::uint32_t> small_;  // alias: work lists, kept to reuse their memory
  std::vector<std::uint32_t> large_;
  std::vector<double> cdf_;          // cdf: running sums, cdf_.back() = total
  std::uint32_t last_positive_ = 0;  // cdf: the last index with P > 0
};

}  // namespace pcbench
