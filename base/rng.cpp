#include "base/rng.h"

#include "base/philox_lanes.h"

#include <immintrin.h>

#include <algorithm>

namespace pcbench {
namespace {

// Round constants of Philox4x32 (Salmon et al. 2011, Section 4; the Random123 values).
constexpr std::uint32_t kMul0 = 0xD2511F53u;
constexpr std::uint32_t kMul1 = 0xCD9E8D57u;
constexpr std::uint32_t kWeyl0 = 0x9E3779B9u;  // golden ratio
constexpr std::uint32_t kWeyl1 = 0xBB67AE85u;  // sqrt(3) - 1

inline void mulhilo(std::uint32_t a, std::uint32_t b, std::uint32_t& hi, std::uint32_t& lo) {
  const std::uint64_t product = static_cast<std::uint64_t>(a) * b;
  hi = static_cast<std::uint32_t>(product >> 32);
  lo = static_cast<std::uint32_t>(product);
}

// SplitMix64 finaliser: a bijective 64-bit mixer (Steele et al. 2014).
inline std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

PhiloxCounter philox4x32_10(PhiloxCounter c, PhiloxKey k) {
  for (int round = 0; round < 10; ++round) {
    std::uint32_t hi0, lo0, hi1, lo1;
    mulhilo(kMul0, c[0], hi0, lo0);
    mulhilo(kMul1, c[2], hi1, lo1);
    c = {hi1 ^ c[1] ^ k[0], lo1, hi0 ^ c[3] ^ k[1], lo0};
    k[0] += kWeyl0;
    k[1] += kWeyl1;
  }
  return c;
}

namespace {

// AVX2: counters computed side by side, each 32-bit word of a lane held in a 64-bit slot, so
// that a lane's 64-bit product is one vpmuludq, its high half one shift, and no word ever moves
// between slots. The high halves of c1 and c3 (and, through the xors, of c0 and c2) carry the
// products' garbage, which vpmuludq ignores; only the low halves are kept at the end. Four
// vectors are in flight (16 lanes) so that the multiplier's latency is hidden.
constexpr std::size_t kSlots = 4;
constexpr std::size_t kVectorsInFlight = 2;
// A tail this short is computed one block at a time (BM_PhiloxFew: below it a padded vector
// costs more than the blocks one by one).
constexpr std::size_t kScalarTail = 4;

// Four counters' words into four vectors of one word each (a 4×4 transpose of 64-bit slots), and
// back: the transpose is its own inverse.
[[gnu::target("avx2")]] inline void transpose(__m256i& a, __m256i& b, __m256i& c, __m256i& d) {
  const __m256i t0 = _mm256_unpacklo_epi64(a, b), t1 = _mm256_unpackhi_epi64(a, b);
  const __m256i t2 = _mm256_unpacklo_epi64(c, d), t3 = _mm256_unpackhi_epi64(c, d);
  a = _mm256_permute2x128_si256(t0, t2, 0x20);
  b = _mm256_permute2x128_si256(t1, t3, 0x20);
  c = _mm256_permute2x128_si256(t0, t2, 0x31);
  d = _mm256_permute2x128_si256(t1, t3, 0x31);
}

// kSlots × vectors full counters (the caller pads a short group).
template <std::size_t kVectors>
[[gnu::target("avx2")]] void philox_lanes_avx2(const PhiloxCounter* in, PhiloxKey k,
                                               PhiloxCounter* out) {
  __m256i c[4][kVectors];
  for (std::size_t v = 0; v < kVectors; ++v) {
    __m256i rows[4];
    for (std::size_t l = 0; l < 4; ++l) {
      rows[l] = _mm256_cvtepu32_epi64(
          _mm_loadu_si128(reinterpret_cast<const __m128i*>(in[v * kSlots + l].data())));
    }
    transpose(rows[0], rows[1], rows[2], rows[3]);
    for (std::size_t w = 0; w < 4; ++w) c[w][v] = rows[w];
  }
  const __m256i mul0 = _mm256_set1_epi64x(kMul0), mul1 = _mm256_set1_epi64x(kMul1);
  for (int round = 0; round < 10; ++round) {
    const __m256i k0 = _mm256_set1_epi64x(k[0]), k1 = _mm256_set1_epi64x(k[1]);
    for (std::size_t v = 0; v < kVectors; ++v) {
      const __m256i p0 = _mm256_mul_epu32(c[0][v], mul0);
      const __m256i p1 = _mm256_mul_epu32(c[2][v], mul1);
      c[0][v] = _mm256_xor_si256(_mm256_xor_si256(_mm256_srli_epi64(p1, 32), c[1][v]), k0);
      c[2][v] = _mm256_xor_si256(_mm256_xor_si256(_mm256_srli_epi64(p0, 32), c[3][v]), k1);
      c[1][v] = p1;
      c[3][v] = p0;
    }
    k[0] += kWeyl0;
    k[1] += kWeyl1;
  }
  const __m256i low_halves = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);
  for (std::size_t v = 0; v < kVectors; ++v) {
    transpose(c[0][v], c[1][v], c[2][v], c[3][v]);
    for (std::size_t l = 0; l < 4; ++l) {
      const __m256i packed = _mm256_permutevar8x32_epi32(c[l][v], low_halves);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(out[v * kSlots + l].data()),
                       _mm256_castsi256_si128(packed));
    }
  }
}

// AVX-512: the same scheme with eight slots to a vector and two vectors in flight (16 lanes).
// A counter's four words go into their vectors' slots, and come back, by two-source permutes of
// whole 512-bit rows rather than AVX2's widening loads and 4×4 transposes: 2.1 against 6.5 ns a
// block, side by side on this machine's AMD EPYC (docs/findings/speed.md, "The generator").
constexpr std::size_t kSlots512 = 8;

// Ten rounds on kVectors vectors of eight lanes, word w of lane l in the low half of slot l of
// c[w][v]; the high halves are don't-cares, as in the AVX2 lanes.
template <std::size_t kVectors>
[[gnu::target("avx512f")]] inline void rounds_avx512(__m512i (&c)[4][kVectors], PhiloxKey k) {
  // The zero-masked forms with every slot kept: the same instructions, and GCC 12's plain forms
  // start from an "undefined" vector that -Wuninitialized reports (GCC bug 105593).
  constexpr __mmask8 kAll = 0xFF;
  const __m512i mul0 = _mm512_set1_epi64(kMul0), mul1 = _mm512_set1_epi64(kMul1);
  for (int round = 0; round < 10; ++round) {
    const __m512i k0 = _mm512_set1_epi64(k[0]), k1 = _mm512_set1_epi64(k[1]);
    for (std::size_t v = 0; v < kVectors; ++v) {
      const __m512i p0 = _mm512_maskz_mul_epu32(kAll, c[0][v], mul0);
      const __m512i p1 = _mm512_maskz_mul_epu32(kAll, c[2][v], mul1);
      // 0x96: the three-way exclusive or.
      c[0][v] = _mm512_ternarylogic_epi64(_mm512_maskz_srli_epi64(kAll, p1, 32), c[1][v], k0, 0x96);
      c[2][v] = _mm512_ternarylogic_epi64(_mm512_maskz_srli_epi64(kAll, p0, 32), c[3][v], k1, 0x96);
      c[1][v] = p1;
      c[3][v] = p0;
    }
    k[0] += kWeyl0;
    k[1] += kWeyl1;
  }
}

// The lanes' blocks into out[0 .. 8 kVectors): (word 0, word 1) and (word 2, word 3) of each lane
// as 64-bit pairs, then each lane's two pairs side by side.
template <std::size_t kVectors>
[[gnu::target("avx512f")]] inline void store_avx512(const __m512i (&c)[4][kVectors],
                                                    PhiloxCounter* out) {
  const __m512i pairs =
      _mm512_setr_epi32(0, 16, 2, 18, 4, 20, 6, 22, 8, 24, 10, 26, 12, 28, 14, 30);
  const __m512i lanes_0_3 = _mm512_setr_epi64(0, 8, 1, 9, 2, 10, 3, 11);
  const __m512i lanes_4_7 = _mm512_setr_epi64(4, 12, 5, 13, 6, 14, 7, 15);
  for (std::size_t v = 0; v < kVectors; ++v) {
    const __m512i low = _mm512_permutex2var_epi32(c[0][v], pairs, c[1][v]);
    const __m512i high = _mm512_permutex2var_epi32(c[2][v], pairs, c[3][v]);
    _mm512_storeu_si512(out[v * kSlots512].data(), _mm512_permutex2var_epi64(low, lanes_0_3, high));
    _mm512_storeu_si512(out[v * kSlots512 + 4].data(),
                        _mm512_permutex2var_epi64(low, lanes_4_7, high));
  }
}

template <std::size_t kVectors>
[[gnu::target("avx512f")]] void philox_lanes_avx512(const PhiloxCounter* in, PhiloxKey k,
                                                    PhiloxCounter* out) {
  __m512i c[4][kVectors];
  for (std::size_t v = 0; v < kVectors; ++v) {
    // Lanes 0-3 in `a`, 4-7 in `b`: word w of lane l is element 4l + w of the pair (b from 16).
    const __m512i a = _mm512_loadu_si512(in[v * kSlots512].data());
    const __m512i b = _mm512_loadu_si512(in[v * kSlots512 + 4].data());
    for (int w = 0; w < 4; ++w) {
      // Into the low half of slot l.
      const __m512i words = _mm512_setr_epi32(w, 0, w + 4, 0, w + 8, 0, w + 12, 0, w + 16, 0,
                                              w + 20, 0, w + 24, 0, w + 28, 0);
      c[w][v] = _mm512_permutex2var_epi32(a, words, b);
    }
  }
  rounds_avx512(c, k);
  store_avx512(c, out);
}

// uniform_of's numbers for a word pair of eight lanes, (hi · 2^32 + lo) >> 11 scaled by 2^-53,
// from two exact conversions of 32-bit halves: hi · 2^21 and lo >> 11 are integers below 2^53
// and 2^21, so their sum is exact and the same double as the 64-bit integer's (no AVX-512DQ).
[[gnu::target("avx512f")]] inline __m512d uniforms_of_avx512(__m512i hi, __m512i lo) {
  constexpr __mmask8 kAll = 0xFF;  // the zero-masked forms, as in rounds_avx512
  const __m256i hi32 = _mm512_maskz_cvtepi64_epi32(kAll, hi);
  const __m256i lo21 = _mm256_srli_epi32(_mm512_maskz_cvtepi64_epi32(kAll, lo), 11);
  const __m512d high = _mm512_mul_pd(_mm512_maskz_cvtepu32_pd(kAll, hi32), _mm512_set1_pd(0x1p21));
  const __m512d sum = _mm512_add_pd(high, _mm512_maskz_cvtepu32_pd(kAll, lo21));
  return _mm512_mul_pd(sum, _mm512_set1_pd(0x1p-53));
}

// 8 kVectors consecutive counters from `first` (word 0 counting up) in the lanes' registers, set
// up there without a counters array, its loads and permutes, or a padded copy, which for a
// stream's few blocks cost as much as their rounds.
template <std::size_t kVectors>
[[gnu::target("avx512f")]] inline void consecutive_counters_avx512(const PhiloxCounter& first,
                                                                   __m512i (&c)[4][kVectors]) {
  for (std::size_t v = 0; v < kVectors; ++v) {
    // Word 0 steps in the low half, wrapping there as ++counter[0] wraps.
    const auto lane = static_cast<std::int64_t>(v * kSlots512);
    c[0][v] = _mm512_add_epi64(_mm512_set1_epi64(first[0]),
                               _mm512_setr_epi64(lane, lane + 1, lane + 2, lane + 3, lane + 4,
                                                 lane + 5, lane + 6, lane + 7));
    for (std::size_t w = 1; w < 4; ++w) c[w][v] = _mm512_set1_epi64(first[w]);
  }
}

// The blocks of 8 kVectors consecutive counters from `first`.
template <std::size_t kVectors>
[[gnu::target("avx512f")]] void philox_blocks_avx512(const PhiloxCounter& first, PhiloxKey k,
                                                     PhiloxCounter* blocks) {
  __m512i c[4][kVectors];
  consecutive_counters_avx512(first, c);
  rounds_avx512(c, k);
  store_avx512(c, blocks);
}

// The same blocks and their uniforms: u[2l] and u[2l + 1] from lane l's words 0-1 and 2-3,
// converted in the lanes.
template <std::size_t kVectors>
[[gnu::target("avx512f")]] void philox_uniforms_avx512(const PhiloxCounter& first, PhiloxKey k,
                                                       PhiloxCounter* blocks, double* u) {
  __m512i c[4][kVectors];
  consecutive_counters_avx512(first, c);
  rounds_avx512(c, k);
  store_avx512(c, blocks);
  const __m512i first_half = _mm512_setr_epi64(0, 8, 1, 9, 2, 10, 3, 11);
  const __m512i second_half = _mm512_setr_epi64(4, 12, 5, 13, 6, 14, 7, 15);
  for (std::size_t v = 0; v < kVectors; ++v) {
    const __m512d a = uniforms_of_avx512(c[0][v], c[1][v]);
    const __m512d b = uniforms_of_avx512(c[2][v], c[3][v]);
    _mm512_storeu_pd(u + 2 * v * kSlots512, _mm512_permutex2var_pd(a, first_half, b));
    _mm512_storeu_pd(u + 2 * v * kSlots512 + kSlots512, _mm512_permutex2var_pd(a, second_half, b));
  }
}

// The blocks of `counters` a full group at a time (`slots` lanes to a vector, kVectorsInFlight
// vectors), and the tail at the narrowest width that holds it: one vector padded, or one block
// at a time when it is that short. A resampling step asks for a few blocks at a time (three
// uniforms a candidate, one per acceptance), and padding those to a whole group computed up to
// eight times the blocks it read (a third of a candidate at M = 4, docs/findings/candidates.md).
template <std::size_t slots, class Full, class Half>
void philox_groups(std::span<const PhiloxCounter> counters, PhiloxKey key,
                   std::span<PhiloxCounter> out, Full&& full, Half&& half) {
  constexpr std::size_t lanes = slots * kVectorsInFlight;
  std::size_t i = 0;
  for (; i + lanes <= counters.size(); i += lanes) full(counters.data() + i, key, out.data() + i);
  const std::size_t tail = counters.size() - i;
  if (tail == 0) return;
  if (tail <= kScalarTail) {
    for (; i < counters.size(); ++i) out[i] = philox4x32_10(counters[i], key);
    return;
  }
  PhiloxCounter in_padded[lanes] = {}, out_padded[lanes];
  std::copy(counters.begin() + static_cast<std::ptrdiff_t>(i), counters.end(), in_padded);
  if (tail <= slots) {
    half(in_padded, key, out_padded);
  } else {
    full(in_padded, key, out_padded);
  }
  std::copy(out_padded, out_padded + tail, out.begin() + static_cast<std::ptrdiff_t>(i));
}

}  // namespace

bool philox_lanes_supported(PhiloxLanes lanes) {
  switch (lanes) {
    case PhiloxLanes::kAvx512:
      return __builtin_cpu_supports("avx512f");
    case PhiloxLanes::kAvx2:
      return __builtin_cpu_supports("avx2");
    case PhiloxLanes::kScalar:
      break;
  }
  return true;
}

void philox4x32_10_many_with(PhiloxLanes lanes, std::span<const PhiloxCounter> counters,
                             PhiloxKey key, std::span<PhiloxCounter> out) {
  switch (lanes) {
    case PhiloxLanes::kAvx512:
      philox_groups<kSlots512>(counters, key, out, philox_lanes_avx512<kVectorsInFlight>,
                               philox_lanes_avx512<1>);
      return;
    case PhiloxLanes::kAvx2:
      philox_groups<kSlots>(counters, key, out, philox_lanes_avx2<kVectorsInFlight>,
                            philox_lanes_avx2<1>);
      return;
    case PhiloxLanes::kScalar:
      break;
  }
  for (std::size_t i = 0; i < counters.size(); ++i) out[i] = philox4x32_10(counters[i], key);
}

void philox_uniforms_with(PhiloxLanes lanes, const PhiloxCounter& first, PhiloxKey key,
                          std::span<PhiloxCounter> blocks, std::span<double> u) {
  const std::size_t n = blocks.size();
  const auto counter = [&first](std::size_t i) {
    PhiloxCounter c = first;
    c[0] += static_cast<std::uint32_t>(i);
    return c;
  };
  if (lanes == PhiloxLanes::kAvx512 && n > kScalarTail) {
    // One call of as many vectors as the blocks need (a call's chain of rounds is its latency,
    // whatever its width up to four vectors), into padded copies.
    PhiloxCounter padded_blocks[kPhiloxUniformGroup];
    double padded_u[2 * kPhiloxUniformGroup];
    switch ((n + kSlots512 - 1) / kSlots512) {
      case 1:
        philox_uniforms_avx512<1>(first, key, padded_blocks, padded_u);
        break;
      case 2:
        philox_uniforms_avx512<2>(first, key, padded_blocks, padded_u);
        break;
      case 3:
        philox_uniforms_avx512<3>(first, key, padded_blocks, padded_u);
        break;
      default:
        philox_uniforms_avx512<4>(first, key, padded_blocks, padded_u);
        break;
    }
    std::copy(padded_blocks, padded_blocks + n, blocks.begin());
    std::copy(padded_u, padded_u + 2 * n, u.begin());
    return;
  }
  if (lanes == PhiloxLanes::kAvx2 && n > kScalarTail) {
    // AVX2's lanes widen and transpose loaded counters anyway: the many path.
    PhiloxCounter counters[kPhiloxUniformGroup];
    for (std::size_t i = 0; i < n; ++i) counters[i] = counter(i);
    philox4x32_10_many_with(lanes, std::span(counters, n), key, blocks);
  } else {
    for (std::size_t i = 0; i < n; ++i) blocks[i] = philox4x32_10(counter(i), key);
  }
  for (std::size_t i = 0; i < n; ++i) {
    u[2 * i] = RandomStream::uniform_of(blocks[i], 0);
    u[2 * i + 1] = RandomStream::uniform_of(blocks[i], 2);
  }
}

namespace {
// Checked once: the widest of AVX-512, AVX2 and one block at a time (the same bits).
PhiloxLanes widest_lanes() {
  static const PhiloxLanes widest =
      philox_lanes_supported(PhiloxLanes::kAvx512) ? PhiloxLanes::kAvx512
      : philox_lanes_supported(PhiloxLanes::kAvx2) ? PhiloxLanes::kAvx2
                                                   : PhiloxLanes::kScalar;
  return widest;
}
}  // namespace

void philox4x32_10_many(std::span<const PhiloxCounter> counters, PhiloxKey key,
                        std::span<PhiloxCounter> out) {
  philox4x32_10_many_with(widest_lanes(), counters, key, out);
}

std::uint64_t run_key(std::uint64_t seed, std::uint64_t run_id_hash) {
  return mix64(mix64(seed ^ 0x7063626E63685F31ull) ^ run_id_hash);
}

void RandomStream::refill() {
  next_ = 0;
  if (ahead_next_ < ahead_end_) {
    block_ = ahead_[ahead_next_++];
    return;
  }
  if (!reads_ahead_) {
    block_ = philox4x32_10(counter_, key_);
    ++counter_[0];
    return;
  }
  static const PhiloxLanes lanes = widest_lanes();
  static_assert(kAhead % kSlots512 == 0, "whole vectors of AVX-512 lanes");
  if (lanes == PhiloxLanes::kAvx512) {
    philox_blocks_avx512<kAhead / kSlots512>(counter_, key_, ahead_);
  } else {
    double unused[2 * kAhead];
    philox_uniforms_with(lanes, counter_, key_, std::span(ahead_, kAhead),
                         std::span(unused, 2 * kAhead));
  }
  counter_[0] += static_cast<std::uint32_t>(kAhead);
  block_ = ahead_[0];
  ahead_next_ = 1;
  ahead_end_ = kAhead;
}

void RandomStream::uniforms(std::span<double> out) {
  std::size_t i = 0;
  // What is left of this block and of the blocks computed ahead.
  while (i < out.size() && (next_ <= 2 || ahead_next_ < ahead_end_)) out[i++] = uniform();
  // A stream that reads ahead and needs fewer blocks than a refill makes (a walk's, between two
  // bounces, for a resampling step of a few candidates): its refill's whole vector of blocks, the
  // rest kept for its next reads, rather than a group of only the blocks needed (the same blocks
  // in the same order either way).
  if (reads_ahead_ && (out.size() - i + 1) / 2 < kAhead) {
    while (i < out.size()) out[i++] = uniform();
    return;
  }
  // Whole blocks, a group at a time, their uniforms converted in the lanes that made them
  // (philox_uniforms_with); the last one stays the stream's block, its words read as far as
  // uniform() would have read them.
  static const PhiloxLanes lanes = widest_lanes();
  PhiloxCounter blocks[kPhiloxUniformGroup];
  double group_u[2 * kPhiloxUniformGroup];
  while (i < out.size()) {
    const std::size_t group = std::min(kPhiloxUniformGroup, (out.size() - i + 1) / 2);
    philox_uniforms_with(lanes, counter_, key_, std::span(blocks, group),
                         std::span(group_u, 2 * group));
    counter_[0] += static_cast<std::uint32_t>(group);
    const std::size_t n = std::min(2 * group, out.size() - i);
    std::copy(group_u, group_u + n, out.begin() + static_cast<std::ptrdiff_t>(i));
    i += n;
    block_ = blocks[group - 1];
    next_ = n % 2 == 1 ? 2 : 4;  // one word pair of the last block read, or both
  }
}

void SampleStreams::fill() {
  // Past the last sample the streams are still well defined (a caller that asks for more gets
  // the next samples' streams).
  const std::size_t group =
      next_sample_ < end_sample_ ? std::min<std::size_t>(kGroup, end_sample_ - next_sample_) : 1;
  for (std::size_t g = 0; g < group; ++g) {
    id_.sample = next_sample_++;
    counters_[g] = RandomStream::first_counter(id_);
  }
  philox4x32_10_many(std::span(counters_).first(group), key_, std::span(blocks_).first(group));
  next_ = 0;
  filled_ = group;
}

}  // namespace pcbench
