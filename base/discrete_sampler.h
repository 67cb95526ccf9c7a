// Drawing indices from a discrete distribution P over a pool of M entries, as probabilistic
// connections do K times per camera sample and a scene's emitter choice once per light sample.
//
// Two ways, both O(M) to build: Vose's alias method (O(1) per draw; M. D. Vose, "A linear
// algorithm for generating random numbers with a given distribution", IEEE TSE 1991) and the
// inverse CDF by binary search (O(log M) per draw). The benchmarks measure which is faster for
// which M and K: the CDF's build is a single pass and wins unless K approaches M. Either way the
// estimator weights a draw by the P it computed, not by what the table implies, so rounding in the
// table cannot bias the estimate.
#pragma once

#include <algorithm>
#include <cstddef>
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
  std::uint32_t draw(RandomStream& rng) const { return resolve(numbers(rng)); }

  // draw() in two halves, for a caller that makes several draws at once: the random numbers of
  // each first, then the table lookups, which miss the cache when the tables are large (pcbpt's
  // are several MB) and then overlap instead of waiting one after the other.
  struct Numbers {
    std::uint32_t column = 0;  // alias: the column
    double u = 0.0;            // alias: to keep the column or take its alias; cdf: the quantile
  };
  Numbers numbers(RandomStream& rng) const {
    if (kind_ == DiscreteSamplerKind::kCdf) return {.u = rng.uniform()};
    const std::uint32_t column = rng.uniform_index(static_cast<std::uint32_t>(columns_.size()));
    return {.column = column, .u = rng.uniform()};
  }
  // Starts the load resolve(numbers) makes (an alias table's column), which misses the cache in a
  // large table, so that it overlaps with the work done before resolve (pcbpt's next draws).
  void prefetch(const Numbers& numbers) const {
    if (kind_ == DiscreteSamplerKind::kAlias) __builtin_prefetch(&columns_[numbers.column]);
  }
  std::uint32_t resolve(const Numbers& numbers) const {
    if (kind_ == DiscreteSamplerKind::kCdf) return index_at(numbers.u);
    const Column column = columns_[numbers.column];
    // A select rather than a branch: the comparison waits on the column's load, and a
    // mispredicted branch there would hold up the lookups queued behind it.
    return numbers.u < column.threshold ? numbers.column : column.alias;
  }

  // An alias table's draw from one uniform u in [0, 1): u·n names the column and, past its
  // integer part, where in the column it falls (the fraction is uniform and independent of the
  // column), so a caller that makes its uniforms in bulk needs one per draw. Branch-free: a
  // resampling candidate picks its emitter this way, and a ternary here was a branch on a coin
  // flip (GCC). Only for a table built as kAlias.
  std::uint32_t pick(double u) const {
    const double x = u * static_cast<double>(columns_.size());
    const std::size_t i = std::min(columns_.size() - 1, static_cast<std::size_t>(x));
    const Column& column = columns_[i];
    const std::uint32_t own =
        0u - static_cast<std::uint32_t>(x - static_cast<double>(i) < column.threshold);
    return (static_cast<std::uint32_t>(i) & own) | (column.alias & ~own);
  }
  // The probability with which an alias table picks each index: what its columns imply, which
  // equals the normalised pmf it was built from up to rounding (for tests).
  std::vector<double> alias_probabilities() const;

  // The inverse CDF at u in [0, 1): the first index whose running sum exceeds u × total. Only for
  // a table built as kCdf (stratified and systematic draws need this map, not just any draw).
  std::uint32_t index_at(double u) const;

 private:
  static constexpr std::size_t kLinearSearchMax = 64;  // inverse CDF by counting up to here

  // Alias column i: keep i with probability `threshold`, else take `alias`. Side by side, so that
  // a draw from a table too large for the cache misses once, not twice (pcbpt draws from tables
  // of several MB).
  struct Column {
    double threshold;
    std::uint32_t alias;
  };

  DiscreteSamplerKind kind_ = DiscreteSamplerKind::kAlias;
  std::vector<Column> columns_;       // alias
  std::vector<std::uint32_t> small_;  // alias: work lists, kept to reuse their memory
  std::vector<std::uint32_t> large_;
  std::vector<double> cdf_;          // cdf: running sums, cdf_.back() = total
  std::uint32_t last_positive_ = 0;  // cdf: the last index with P > 0
};

}  // namespace pcbench
