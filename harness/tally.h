// Running statistics of per-sample estimates: Welford's update within a chunk, Chan et al.'s
// pairwise merge across chunks, a Neumaier-compensated sum for the mean, non-finite samples
// counted (never dropped) with the first one located, and a small reservoir of the largest |x|
// for the tail diagnostic.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>

namespace pcbench {

// Neumaier's variant of Kahan summation: exact to within one rounding for sums whose terms vary
// in sign and magnitude, which plain summation over 10^7 samples is not.
class CompensatedSum {
 public:
  void add(double x) {
    const double t = sum_ + x;
    if (std::fabs(sum_) >= std::fabs(x)) {
      compensation_ += (sum_ - t) + x;
    } else {
      compensation_ += (x - t) + sum_;
    }
    sum_ = t;
  }
  void add(const CompensatedSum& other) {
    add(other.sum_);
    add(other.compensation_);
  }
  double value() const { return sum_ + compensation_; }

 private:
  double sum_ = 0.0;
  double compensation_ = 0.0;
};

// The k largest |x| seen, kept for the tail-index diagnostic of the verifier.
class LargestValues {
 public:
  static constexpr std::size_t kCapacity = 16;

  void add(double magnitude) {
    if (size_ < kCapacity) {
      values_[size_++] = magnitude;
      if (size_ == kCapacity) find_smallest();
      return;
    }
    if (magnitude <= values_[smallest_]) return;
    values_[smallest_] = magnitude;
    find_smallest();
  }
  void merge(const LargestValues& other) {
    for (std::size_t i = 0; i < other.size_; ++i) add(other.values_[i]);
  }
  // Largest first.
  std::size_t sorted(std::span<double, kCapacity> out) const;

 private:
  void find_smallest();

  std::array<double, kCapacity> values_{};
  std::size_t size_ = 0;
  std::size_t smallest_ = 0;
};

class Tally {
 public:
  // Adds the estimate of sample `sample_index` (the index is only kept if x is not finite).
  void add(double x, std::uint64_t sample_index) {
    if (!std::isfinite(x)) [[unlikely]] {
      add_nonfinite(x, sample_index);
      return;
    }
    ++n_;
    sum_.add(x);
    const double delta = x - mean_;
    mean_ += delta / static_cast<double>(n_);
    m2_ += delta * (x - mean_);
    largest_.add(std::fabs(x));
  }

  // Chan et al.'s merge. `later` must hold samples that come after this tally's in sample order,
  // so that the first non-finite sample stays the first; merge chunks in order for bitwise
  // reproducible results.
  void merge(const Tally& later);

  std::uint64_t finite_count() const { return n_; }
  std::uint64_t nonfinite_count() const { return nonfinite_; }
  std::uint64_t count() const { return n_ + nonfinite_; }

  // Mean over all samples; non-finite samples propagate into it (they are never dropped).
  double mean() const;
  // Unbiased sample variance of the finite samples (n - 1 in the denominator); NaN if n < 2.
  double variance_of_finite() const;
  // Variance of all samples: NaN once any sample was not finite.
  double variance() const {
    return nonfinite_ > 0 ? std::numeric_limits<double>::quiet_NaN() : variance_of_finite();
  }
  std::optional<std::uint64_t> first_nonfinite_sample() const { return first_nonfinite_; }
  const LargestValues& largest() const { return largest_; }

 private:
  void add_nonfinite(double x, std::uint64_t sample_index);

  std::uint64_t n_ = 0;
  CompensatedSum sum_;
  double mean_ = 0.0;  // Welford's running mean, used for m2_ only
  double m2_ = 0.0;
  std::uint64_t nonfinite_ = 0;
  double nonfinite_sum_ = 0.0;  // inf + -inf gives NaN, as the true sum would
  std::optional<std::uint64_t> first_nonfinite_;
  LargestValues largest_;
};

}  // namespace pcbench
