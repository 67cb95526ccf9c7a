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
  small_.resize(m);
  large_.resize(m);
  const double scale = static_cast<double>(m) / total;
  // The two work lists as stacks over arrays of m with their sizes in locals: as vectors, each
  // push and pop stored the vector's end back to the sampler and the next step read it again, a
  // chain through memory on every step (pcbpt builds a table per cache point and iteration).
  Column* columns = columns_.data();
  std::uint32_t* small = small_.data();
  std::uint32_t* large = large_.data();
  std::uint32_t smalls = 0, larges = 0;
  for (std::uint32_t i = 0; i < m; ++i) {
    const double threshold = pmf[i] * scale;
    columns[i] = {.threshold = threshold, .alias = i};
    // Written to both lists and counted in one, without a branch on which: random data would
    // mispredict it.
    const bool is_small = threshold < 1.0;
    small[smalls] = i;
    large[larges] = i;
    smalls += is_small ? 1 : 0;
    larges += is_small ? 0 : 1;
  }
  while (smalls > 0 && larges > 0) {
    const std::uint32_t s = small[--smalls];
    const std::uint32_t l = large[larges - 1];
    columns[s].alias = l;
    columns[l].threshold -= 1.0 - columns[s].threshold;
    if (columns[l].threshold < 1.0) {
      --larges;
      small[smalls++] = l;
    }
  }
  // What is left is full up to rounding: keep it always.
  for (std::uint32_t k = 0; k < smalls; ++k) columns[small[k]].threshold = 1.0;
  for (std::uint32_t k = 0; k < larges; ++k) columns[large[k]].threshold = 1.0;
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
