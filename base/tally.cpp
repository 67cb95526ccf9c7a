#include "base/tally.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <functional>

namespace pcbench {

std::vector<double> LargestValues::sorted() const {
  std::vector<double> out(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(size_));
  std::sort(out.begin(), out.end(), std::greater<>());
  if (out.size() > capacity_) out.resize(capacity_);
  return out;
}

namespace {

// Doubles order as these keys do as unsigned integers (-0 below +0; NaN, which a tally never
// keeps, above +inf): the bits of a non-negative value with the top bit set, the complement of a
// negative one's.
constexpr std::uint64_t kTopBit = std::uint64_t{1} << 63;
std::uint64_t order_key(double v) {
  const auto bits = std::bit_cast<std::uint64_t>(v);
  return (bits & kTopBit) != 0 ? ~bits : bits | kTopBit;
}
double value_of_key(std::uint64_t key) {
  return std::bit_cast<double>((key & kTopBit) != 0 ? key & ~kTopBit : ~key);
}

}  // namespace

// The k-th largest by a radix select on the keys, eight bits at a time from the highest bit in
// which they differ: a few passes without a branch on the data (nth_element's comparisons
// mispredicted about half the time, and trimming was a tenth of a cheap run). Then the values
// above it, and it as many times as the k need: the k largest of the buffer, as a multiset.
void LargestValues::trim() {
  thread_local std::vector<std::uint64_t> candidates;
  candidates.resize(size_);
  std::uint64_t all_or = 0, all_and = ~std::uint64_t{0};
  for (std::size_t i = 0; i < size_; ++i) {
    const std::uint64_t key = order_key(buffer_[i]);
    candidates[i] = key;
    all_or |= key;
    all_and &= key;
  }
  std::size_t count = size_;
  std::size_t rank = capacity_;  // the one wanted is the rank-th largest candidate
  const int differing = std::bit_width(all_or ^ all_and);
  for (int shift = std::max(differing - 8, 0); differing > 0; shift = std::max(shift - 8, 0)) {
    std::array<std::uint32_t, 256> histogram{};
    for (std::size_t i = 0; i < count; ++i) ++histogram[(candidates[i] >> shift) & 0xFF];
    std::size_t above = 0;
    std::uint64_t digit = 255;
    while (above + histogram[digit] < rank) above += histogram[digit--];
    rank -= above;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint64_t key = candidates[i];
      candidates[kept] = key;
      kept += ((key >> shift) & 0xFF) == digit ? 1 : 0;
    }
    count = kept;
    if (shift == 0) break;
  }
  // Every candidate left is the k-th largest; `rank` copies of it complete the k.
  const std::uint64_t kth = candidates[0];
  std::size_t kept = 0;
  for (std::size_t i = 0; i < size_; ++i) {
    const double v = buffer_[i];
    buffer_[kept] = v;
    kept += order_key(v) > kth ? 1 : 0;
  }
  cut_ = value_of_key(kth);  // a value equal to it can no longer enter the top k
  std::fill_n(buffer_.begin() + static_cast<std::ptrdiff_t>(kept), rank, cut_);
  size_ = kept + rank;
}

void Tally::merge(const Tally& later) {
  Finite& a = finite_;
  const Finite& b = later.finite_;
  if (b.n > 0) {
    if (a.n == 0) {
      a.mean = b.mean;
      a.m2 = b.m2;
    } else {
      const double na = static_cast<double>(a.n);
      const double nb = static_cast<double>(b.n);
      const double n = na + nb;
      const double delta = b.mean - a.mean;
      a.mean += delta * (nb / n);
      a.m2 += b.m2 + delta * delta * (na * nb / n);
    }
    a.n += b.n;
    a.sum.add(b.sum);
    largest_.merge(later.largest_);
    a.nonzero += b.nonzero;
    a.sum_abs += b.sum_abs;
    a.sum_squares += b.sum_squares;
  }
  if (later.nonfinite_ > 0) {
    if (!first_nonfinite_) first_nonfinite_ = later.first_nonfinite_;
    nonfinite_ += later.nonfinite_;
    nonfinite_sum_ += later.nonfinite_sum_;
  }
}

double Tally::mean() const {
  const std::uint64_t total = count();
  if (total == 0) return std::numeric_limits<double>::quiet_NaN();
  return (finite_.sum.value() + nonfinite_sum_) / static_cast<double>(total);
}

double Tally::variance_of_finite() const {
  if (finite_.n < 2) return std::numeric_limits<double>::quiet_NaN();
  return finite_.m2 / static_cast<double>(finite_.n - 1);
}

void Tally::add_nonfinite(double x, std::uint64_t sample_index) {
  if (!first_nonfinite_) first_nonfinite_ = sample_index;
  ++nonfinite_;
  nonfinite_sum_ += x;
}

}  // namespace pcbench
