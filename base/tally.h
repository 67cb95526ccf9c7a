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
// current cut go to a buffer of 2k; when it is full, the k largest are kept and the cut raised to
// the k-th. Amortised O(1) per sample. A value is written to the buffer whether it enters or not
// and only the count moves, so that a sample costs no branch on its value (a run's tail enters at
// unpredictable samples: a branch there mispredicted on a third of a cheap integrand's samples).
class LargestValues {
 public:
  explicit LargestValues(std::size_t capacity)
      : capacity_(capacity), buffer_(capacity == 0 ? 0 : 2 * capacity) {}
  static constexpr std::size_t kDefaultCapacity = 16;

  void add(double magnitude) {
    Cursor cursor = begin();
    cursor.add(magnitude);
    end(cursor);
  }

  // The buffer's state for a loop of adds, held in locals (registers) rather than re-read from
  // the object after every store: begin(), Cursor::add per value, end().
  class Cursor {
   public:
    void add(double magnitude) {
      if (limit_ == 0) return;  // capacity 0: nothing is kept
      data_[size_] = magnitude;
      size_ += !(magnitude <= cut_) ? 1 : 0;  // enters unless at or below the cut (NaN enters)
      if (size_ == limit_) [[unlikely]] {
        owner_->size_ = size_;
        owner_->trim();
        size_ = owner_->size_;
        cut_ = owner_->cut_;
      }
    }

   private:
    friend class LargestValues;
    LargestValues* owner_;
    double* data_;
    std::size_t size_;
    std::size_t limit_;
    double cut_;
  };
  Cursor begin() {
    Cursor cursor;
    cursor.owner_ = this;
    cursor.data_ = buffer_.data();
    cursor.size_ = size_;
    cursor.limit_ = buffer_.size();
    cursor.cut_ = cut_;
    return cursor;
  }
  void end(const Cursor& cursor) { size_ = cursor.size_; }
  void merge(const LargestValues& other) {
    for (std::size_t i = 0; i < other.size_; ++i) add(other.buffer_[i]);
  }
  // Largest first, at most k. The values kept are the k largest of the multiset seen, so they do
  // not depend on the order of adds and merges.
  std::vector<double> sorted() const;
  std::size_t capacity() const { return capacity_; }

 private:
  void trim();

  std::size_t capacity_;
  double cut_ = -std::numeric_limits<double>::infinity();  // below it nothing can be kept
  std::vector<double> buffer_;  // [0, size_) kept so far; the rest scratch
  std::size_t size_ = 0;
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
    finite_.add(x);
    largest_.add(std::fabs(x));
  }

  // add(next(), first_index + i) for i < count, in order: the same operations, with the running
  // state in locals for the loop (a fused sampling loop calls this with the sample's estimate as
  // next, inlined).
  template <typename Next>
  void add_each(std::uint64_t first_index, std::uint64_t count, Next&& next) {
    Finite finite = finite_;
    LargestValues::Cursor largest = largest_.begin();
    for (std::uint64_t i = 0; i < count; ++i) {
      const double x = next();
      if (!std::isfinite(x)) [[unlikely]] {
        add_nonfinite(x, first_index + i);
        continue;
      }
      finite.add(x);
      largest.add(std::fabs(x));
    }
    finite_ = finite;
    largest_.end(largest);
  }

  // Chan et al.'s merge. `later` must hold samples that come after this tally's in sample order,
  // so that the first non-finite sample stays the first; merge chunks in order for bitwise
  // reproducible results.
  void merge(const Tally& later);

  std::uint64_t finite_count() const { return finite_.n; }
  std::uint64_t nonfinite_count() const { return nonfinite_; }
  std::uint64_t count() const { return finite_.n + nonfinite_; }

  // Mean over all samples; non-finite samples propagate into it (they are never dropped).
  double mean() const;
  // Sum of all samples (compensated), non-finite ones included.
  double sum() const { return finite_.sum.value() + nonfinite_sum_; }
  // Unbiased sample variance of the finite samples (n - 1 in the denominator); NaN if n < 2.
  double variance_of_finite() const;
  // Variance of all samples: NaN once any sample was not finite.
  double variance() const {
    return nonfinite_ > 0 ? std::numeric_limits<double>::quiet_NaN() : variance_of_finite();
  }
  std::optional<std::uint64_t> first_nonfinite_sample() const { return first_nonfinite_; }
  const LargestValues& largest() const { return largest_; }
  std::uint64_t nonzero_count() const { return finite_.nonzero; }
  // Kish's effective sample size of the finite samples, (Σ |x|)² / Σ x²: n for samples of one
  // magnitude, about 1 when one sample dominates (a peak hit once). 0 when all are 0.
  double effective_sample_size() const {
    return finite_.sum_squares > 0.0 ? finite_.sum_abs * finite_.sum_abs / finite_.sum_squares
                                     : 0.0;
  }
  double sum_of_squares() const { return finite_.sum_squares; }

 private:
  // What the finite samples add up to.
  struct Finite {
    std::uint64_t n = 0;
    CompensatedSum sum;
    double mean = 0.0;  // Welford's running mean, used for m2 only
    double m2 = 0.0;
    std::uint64_t nonzero = 0;
    double sum_abs = 0.0;  // diagnostics only: plain sums in a fixed order
    double sum_squares = 0.0;

    void add(double x) {
      ++n;
      sum.add(x);
      const double delta = x - mean;
      mean += delta / static_cast<double>(n);
      m2 += delta * (x - mean);
      if (x != 0.0) ++nonzero;
      sum_abs += std::fabs(x);
      sum_squares += x * x;
    }
  };

  void add_nonfinite(double x, std::uint64_t sample_index);

  Finite finite_;
  std::uint64_t nonfinite_ = 0;
  double nonfinite_sum_ = 0.0;  // inf + -inf gives NaN, as the true sum would
  std::optional<std::uint64_t> first_nonfinite_;
  LargestValues largest_;
};

}  // namespace pcbench
