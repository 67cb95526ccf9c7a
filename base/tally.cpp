#include "base/tally.h"

#include <algorithm>
#include <functional>

namespace pcbench {

std::vector<double> LargestValues::sorted() const {
  std::vector<double> out = buffer_;
  std::sort(out.begin(), out.end(), std::greater<>());
  if (out.size() > capacity_) out.resize(capacity_);
  return out;
}

void LargestValues::trim() {
  const auto kth = buffer_.begin() + static_cast<std::ptrdiff_t>(capacity_ - 1);
  std::nth_element(buffer_.begin(), kth, buffer_.end(), std::greater<>());
  cut_ = *kth;  // the k-th largest: a value equal to it can no longer enter the top k
  buffer_.resize(capacity_);
}

void Tally::merge(const Tally& later) {
  if (later.n_ > 0) {
    if (n_ == 0) {
      mean_ = later.mean_;
      m2_ = later.m2_;
    } else {
      const double na = static_cast<double>(n_);
      const double nb = static_cast<double>(later.n_);
      const double n = na + nb;
      const double delta = later.mean_ - mean_;
      mean_ += delta * (nb / n);
      m2_ += later.m2_ + delta * delta * (na * nb / n);
    }
    n_ += later.n_;
    sum_.add(later.sum_);
    largest_.merge(later.largest_);
    nonzero_ += later.nonzero_;
    sum_abs_ += later.sum_abs_;
    sum_squares_ += later.sum_squares_;
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
  return (sum_.value() + nonfinite_sum_) / static_cast<double>(total);
}

double Tally::variance_of_finite() const {
  if (n_ < 2) return std::numeric_limits<double>::quiet_NaN();
  return m2_ / static_cast<double>(n_ - 1);
}

void Tally::add_nonfinite(double x, std::uint64_t sample_index) {
  if (!first_nonfinite_) first_nonfinite_ = sample_index;
  ++nonfinite_;
  nonfinite_sum_ += x;
}

}  // namespace pcbench
