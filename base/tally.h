// Running statistics of per-sample estimates: Welford's update within a chunk, Chan et al.'s
// pairwise merge across chunks, a Neumaier-compensated sum for the mean, non-finite samples
// counted (never dropped) with the first one located, the largest |x| for the tail diagnostic,
// and the non-zero count and effective sample size for the low-count guard.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <vector>

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

// The k largest |x| seen, kept for the tail-shape diagnostic of the verifier. Values above the
// current cut go to a buffer of up to 2k; when it is full, nth_element keeps the k largest and
// raises the cut. Amortised O(1) per sample, and most samples cost one comparison.
class LargestValues {
 public:
  explicit LargestValues(std::size_t capacity) : capacity_(capacity) {}
  static constexpr std::size_t kDefaultCapacity = 16;

  void add(double magnitude) {
    if (capacity_ == 0 || magnitude <= cut_) return;
    buffer_.push_back(magnitude);
    if (buffer_.size() >= 2 * capacity_) trim();
  }
  void merge(const LargestValues& other) {
    for (double v : other.buffer_) add(v);
  }
  // Largest first, at most k. The values kept are the k largest of the multiset seen, so they do
  // not depend on the order of adds and merges.
  std::vector<double> sorted() const;
  std::size_t capacity() const { return capacity_; }

 private:
  void trim();

  std::size_t capacity_;
  double cut_ = -std::numeric_limits<double>::infinity();  // below it nothing can be kept
  std::vector<double> buffer_;
};

class Tally {
 public:
  Tally() : Tally(LargestValues::kDefaultCapacity) {}
  explicit Tally(std::size_t largest_capacity) : largest_(largest_capacity) {}

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
    const double magnitude = std::fabs(x);
    largest_.add(magnitude);
    if (x != 0.0) ++nonzero_;
    sum_abs_ += magnitude;
    sum_squares_ += x * x;
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
  // Sum of all samples (compensated), non-finite ones included.
  double sum() const { return sum_.value() + nonfinite_sum_; }
  // Unbiased sample variance of the finite samples (n - 1 in the denominator); NaN if n < 2.
  double variance_of_finite() const;
  // Variance of all samples: NaN once any sample was not finite.
  double variance() const {
    return nonfinite_ > 0 ? std::numeric_limits<double>::quiet_NaN() : variance_of_finite();
  }
  std::optional<std::uint64_t> first_nonfinite_sample() const { return first_nonfinite_; }
  const LargestValues& largest() const { return largest_; }
  std::uint64_t nonzero_count() const { return nonzero_; }
  // Kish's effective sample size of the finite samples, (Σ |x|)² / Σ x²: n for samples of one
  // magnitude, about 1 when one sample dominates (a peak hit once). 0 when all are 0.
  double effective_sample_size() const {
    return sum_squares_ > 0.0 ? sum_abs_ * sum_abs_ / sum_squares_ : 0.0;
  }
  double sum_of_squares() const { return sum_squares_; }

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
  std::uint64_t nonzero_ = 0;
  double sum_abs_ = 0.0;  // diagnostics only: plain sums in a fixed order
  double sum_squares_ = 0.0;
};

}  // namespace pcbench
