#include "base/discrete_sampler.h"

#include <algorithm>

namespace pcbench {

void DiscreteSampler::build(std::span<const double> pmf, DiscreteSamplerKind kind) {
  kind_ = kind;
  const auto m = static_cast<std::uint32_t>(pmf.size());
  if (kind == DiscreteSamplerKind::kCdf) {
    cdf_.resize(m);
    double running = 0.0;
    last_positive_ = 0;
    for (std::uint32_t i = 0; i < m; ++i) {
      cdf_[i] = running += pmf[i];
      if (pmf[i] > 0.0) last_positive_ = i;
    }
    return;
  }

  // Vose: scale to mean 1, then pair each under-full column with an over-full one. (The CDF's
  // total is its last running sum: it needs no pass of its own.)
  double total = 0.0;
  for (double p : pmf) total += p;
  columns_.resize(m);
  small_.clear();
  large_.clear();
  const double scale = static_cast<double>(m) / total;
  for (std::uint32_t i = 0; i < m; ++i) {
    columns_[i] = {.threshold = pmf[i] * scale, .alias = i};
    (columns_[i].threshold < 1.0 ? small_ : large_).push_back(i);
  }
  while (!small_.empty() && !large_.empty()) {
    const std::uint32_t s = small_.back();
    small_.pop_back();
    const std::uint32_t l = large_.back();
    columns_[s].alias = l;
    columns_[l].threshold -= 1.0 - columns_[s].threshold;
    if (columns_[l].threshold < 1.0) {
      large_.pop_back();
      small_.push_back(l);
    }
  }
  // What is left is full up to rounding: keep it always.
  for (std::uint32_t i : small_) columns_[i].threshold = 1.0;
  for (std::uint32_t i : large_) columns_[i].threshold = 1.0;
}

std::vector<double> DiscreteSampler::alias_probabilities() const {
  const double n = static_cast<double>(columns_.size());
  std::vector<double> p(columns_.size(), 0.0);
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    p[i] += columns_[i].threshold / n;
    p[columns_[i].alias] += (1.0 - columns_[i].threshold) / n;
  }
  return p;
}

std::uint32_t DiscreteSampler::index_at(double u) const {
  // First entry whose running sum exceeds the target: zero-probability entries are never chosen.
  // (The target can round up to the total; then the last entry that can be drawn is taken.)
  const double target = u * cdf_.back();
  std::size_t index = 0;
  if (cdf_.size() <= kLinearSearchMax) {
    // The running sums are sorted, so the first one above the target is at the count of those
    // at or below it: the same index as upper_bound, without its unpredictable branches (a
    // binary search over 16 entries cost more than the rest of the resampling step; measured
    // with pcbench_bench --benchmark_filter=ImportanceStep).
    // Four counts, one per lane of four: a single count was a chain of dependent additions
    // (comparison, then add with carry) through all M entries, 6% of the default suite.
    const std::size_t size = cdf_.size();
    const double* c = cdf_.data();
    std::size_t lanes[4] = {0, 0, 0, 0};
    std::size_t i = 0;
    for (; i + 4 <= size; i += 4) {
      for (std::size_t lane = 0; lane < 4; ++lane) lanes[lane] += c[i + lane] <= target ? 1 : 0;
    }
    for (; i < size; ++i) lanes[0] += c[i] <= target ? 1 : 0;
    index = lanes[0] + lanes[1] + lanes[2] + lanes[3];
  } else {
    index =
        static_cast<std::size_t>(std::upper_bound(cdf_.begin(), cdf_.end(), target) - cdf_.begin());
  }
  return index == cdf_.size() ? last_positive_ : static_cast<std::uint32_t>(index);
}

}  // namespace pcbench
