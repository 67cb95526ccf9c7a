// Counter-based random numbers: Philox4x32-10 (Salmon et al., "Parallel random numbers: as easy as
// 1, 2, 3", SC 2011).
//
// Every random number pcbench uses is a pure function of (key, counter). The key comes from the
// seed and the run id; the counter names what the number is for: replicate, purpose (pool, camera
// path, resampling draw), the sample (or batch) index, the path within it, and the dimension.
// Nothing depends on which thread asks, in which order, or what ran before, so a run's numbers
// are the same for any thread count, suite order or sharding.
#pragma once

#include <array>
#include <cstdint>
#include <span>

namespace pcbench {

using PhiloxCounter = std::array<std::uint32_t, 4>;
using PhiloxKey = std::array<std::uint32_t, 2>;

// One Philox4x32 block: 4 independent 32-bit outputs for one (counter, key).
PhiloxCounter philox4x32_10(PhiloxCounter counter, PhiloxKey key);

// The blocks of many counters under one key: out[i] = philox4x32_10(counters[i], key), computed
// several lanes at a time in SIMD registers, which a single block's chain of dependent
// multiplications cannot use (about 3x fewer cycles per block; BM_PhiloxMany). out.size() must
// equal counters.size().
void philox4x32_10_many(std::span<const PhiloxCounter> counters, PhiloxKey key,
                        std::span<PhiloxCounter> out);

// What a stream of numbers is used for. Each purpose gets disjoint counters, so that no
// resampling draw reuses the numbers that made a pool (docs/reference/INTERFACE.md, "Determinism").
enum class StreamPurpose : std::uint8_t {
  kLightPool = 1,    // the M light paths a camera path may connect to
  kCameraPath = 2,   // the camera path y of a sample
  kResampling = 3,   // draws xi_k from the pool
  kEstimatorAux = 4  // anything else an estimator needs (e.g. stochastic mixing)
};

// 64-bit key of one run under one seed: mixes the seed with the run id so that two runs of a
// suite never share numbers, while a run's numbers do not depend on its place in the suite.
std::uint64_t run_key(std::uint64_t seed, std::uint64_t run_id_hash);

// Names one stream: a sequence of uniforms for one path of one sample of one replicate.
struct StreamId {
  std::uint64_t key = 0;
  std::uint32_t replicate = 0;  // < 2^24
  StreamPurpose purpose = StreamPurpose::kLightPool;
  std::uint32_t sample = 0;  // sample index, or batch index for a shared pool
  std::uint32_t path = 0;    // path within the sample's pool, draw index, ...
};

// A stream of uniforms in [0, 1) from consecutive Philox blocks. Cheap to construct: make one
// per path rather than sharing one across paths, so that the dimensions one path consumes never
// shift the numbers of another.
class RandomStream {
 public:
  explicit RandomStream(const StreamId& id) : key_(key_of(id)), counter_(first_counter(id)) {}
  // The same stream, its first block already computed (by philox4x32_10_many from
  // first_counter(id) under key_of(id)): the same numbers as RandomStream(id), without the first
  // refill.
  RandomStream(const StreamId& id, const PhiloxCounter& first_block)
      : RandomStream(key_of(id), first_counter(id), first_block) {}
  // The same, from the stream's key and first counter as the caller computed them.
  RandomStream(const PhiloxKey& key, const PhiloxCounter& first_counter,
               const PhiloxCounter& first_block)
      : key_(key), counter_(first_counter), block_(first_block), next_(0) {
    ++counter_[0];
  }

  static PhiloxKey key_of(const StreamId& id) {
    return {static_cast<std::uint32_t>(id.key), static_cast<std::uint32_t>(id.key >> 32)};
  }
  // Counter layout: [block, path, sample, replicate (24 bits) | purpose (8 bits)].
  static PhiloxCounter first_counter(const StreamId& id) {
    return {0u, id.path, id.sample,
            (id.replicate & 0x00FFFFFFu) | (static_cast<std::uint32_t>(id.purpose) << 24)};
  }

  // Uniform double in [0, 1) with 53 random bits; never returns 1.
  double uniform() {
    if (next_ > 2) refill();  // needs two words
    const double u = uniform_of(block_, next_);
    next_ += 2;
    return u;
  }
  // The uniform that words `word` and `word + 1` of `block` give: a stream's first two uniforms
  // are uniform_of(first block, 0) and uniform_of(first block, 2), without a stream.
  static double uniform_of(const PhiloxCounter& block, int word) {
    const std::uint64_t hi = block[static_cast<std::size_t>(word)];
    const std::uint64_t lo = block[static_cast<std::size_t>(word) + 1];
    return static_cast<double>(((hi << 32) | lo) >> 11) * 0x1.0p-53;
  }

  // The next out.size() uniforms, the numbers uniform() would give one call at a time, their
  // blocks computed many at a time (philox4x32_10_many): a resampling step reads three per
  // candidate, and one block at a time those refills were a sixth of a candidate's cost.
  void uniforms(std::span<double> out);

  // For a stream that will read many blocks (a path's walk, its connections' draws): its refills
  // then compute kAhead blocks at once in SIMD lanes and hand them out one by one. A block's ten
  // rounds are a chain of dependent multiplications, so one costs nearly what eight side by side
  // do: a sixth of a path's refill time, where a stream that reads two or three blocks would
  // lose by it (BM_ImportanceStep). Sixteen (two AVX-512 vectors in flight) rather than eight:
  // a walk with resampled next events reads that many and more (docs/findings/candidates.md).
  // The numbers are the same either way.
  void read_ahead() { reads_ahead_ = true; }

  // Uniform integer in [0, n) for n >= 1 (Lemire's multiply-shift; bias < n / 2^32).
  std::uint32_t uniform_index(std::uint32_t n) {
    if (next_ >= 4) refill();
    const std::uint64_t r = block_[next_++];
    return static_cast<std::uint32_t>((r * n) >> 32);
  }

 private:
  void refill();

  static constexpr std::size_t kAhead = 16;

  PhiloxKey key_;
  PhiloxCounter counter_;  // counter_[0] counts blocks
  PhiloxCounter block_{};
  int next_ = 4;
  bool reads_ahead_ = false;
  std::uint8_t ahead_next_ = 0, ahead_end_ = 0;
  PhiloxCounter ahead_[kAhead];  // blocks ahead_next_ .. ahead_end_ not yet read
};

// The streams of consecutive samples that share everything else (purpose, path): next() is
// RandomStream(id with sample = first_sample + i) for i = 0, 1, ..., the same numbers, with the
// first blocks computed a group at a time by philox4x32_10_many rather than by each stream's
// first refill (a resampling step's draws: one scalar block per camera sample was 8% of a pool
// estimator's run).
class SampleStreams {
 public:
  SampleStreams(const StreamId& id, std::uint32_t first_sample, std::uint32_t count)
      : id_(id),
        key_(RandomStream::key_of(id)),
        next_sample_(first_sample),
        end_sample_(first_sample + count) {}

  RandomStream next() {
    if (next_ == filled_) fill();
    const std::size_t g = next_++;
    return RandomStream(key_, counters_[g], blocks_[g]);
  }

 private:
  static constexpr std::size_t kGroup = 64;  // small: the blocks are read while still in L1
  void fill();

  StreamId id_;
  PhiloxKey key_;
  std::uint32_t next_sample_, end_sample_;  // the samples whose blocks are not yet computed
  std::array<PhiloxCounter, kGroup> counters_{}, blocks_{};
  std::size_t next_ = 0, filled_ = 0;
};

}  // namespace pcbench
